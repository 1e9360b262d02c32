// CVODE for an explicit-ODE ldae_model (see Integrator.h and
// ldae_model::explicit_ode): y' = f(t, y) = -F(t, y, 0) and df/dy =
// -dF/dy, so the model's residual and Jacobian serve unchanged. BDF with
// Newton iteration and the dense or KLU solver for stiff models; Adams with
// fixed-point iteration (no Jacobian) for non-stiff ones.
//
// And for a linearly implicit one (ldae_model::n_ode = n, `--method
// sga|ode`): f and df/dy from ImplicitOde, the start projected onto the
// constraints, and with project_constraints every step too (CVODE's
// projection for BDF; for Adams, which CVODE 6.4 does not project, a
// restart from the projected point once the drift exceeds the tolerance)
// and every output row. `Auto` starts with Adams and moves to BDF when a
// decaying mode holds Adams' step at its stability bound.
#pragma once

#include "integrators/Integrator.h"

#include <Eigen/Dense>

namespace ldae::runtime {

class CvodeIntegrator final : public Integrator {
public:
  enum class Lmm { Bdf, Adams, Auto };
  CvodeIntegrator(const ModelEval &ev, Lmm lmm);
  ~CvodeIntegrator() override;

  const char *name() const override { return name_.c_str(); }
  Expected<bool> init(int set, double t0, const double *y, const double *yp,
                      double rtol, const std::vector<double> &atol,
                      double tstop, bool errorTestAlgebraic) override;
  Expected<bool> reinit(int set, double t, const double *y,
                        const double *yp) override;
  void nextReinitAfterEvent(const std::vector<int> &held) override {
    afterEvent_ = true;
    heldAfterEvent_ = held;
  }
  /// y' = f(t0, y): every unknown of an ODE is differential (a linearly
  /// implicit model's start is projected onto its constraints first).
  StepStatus completeStart(double tout1) override;
  Expected<bool> setStopTime(double tstop) override;
  Expected<bool> setMaxStep(double hmax) override;
  StepStatus step(double &tret) override;
  Expected<bool> interpolate(double t, double *y, double *yp) override;
  const double *y() const override;
  const double *yp() const override;
  void addCounters(SimStats &stats) const override;
  std::vector<int> rootsFound() const override;
  std::vector<double> weightedErrors() const override;
  double currentTime() const override;
  double lastStep() const override;
  double iterationCj() const override;

private:
  Expected<bool> create(double t0);
  Expected<bool> setupSolver();
  Expected<bool> restartAt(double t, const double *y);
  /// y onto the constraints by the start's rule (fixed start values held
  /// before the first step), and the Adams stabilization rate there.
  /// Seed 002's rule on the model as written (ldae_model::written_*): y
  /// moves along T(E, F) at (t, y, y') onto every constraint; the unknowns
  /// `held` keep their values (the fixed start values at the start, the
  /// reinit targets after an event); y' null: the field's. False,
  /// y untouched, without the pencil or where the constraints cannot be
  /// met along T (the nearest point then decides).
  /// The unknowns with a fixed start value.
  std::vector<int> fixedUnknowns() const;
  bool jumpOntoConstraints(double t, double *y, const double *yp,
                           const std::vector<int> &held);
  StepStatus startOnConstraints(double t, double *y);
  void saveCounters();
  void updateName();
  /// The projection restart and the stiffness check after an Adams step of
  /// a linearly implicit model.
  StepStatus afterAdamsStep(double t);
  /// The periodic look at df/dy's spectrum during Adams: raises the
  /// stabilization rate to the radius seen there, and returns whether the
  /// field looks stiff (under `auto`; false otherwise).
  bool inspectSpectrum();
  /// gamma from the start's norm and the largest radius seen (kRateCap).
  void raiseStabilization(const Eigen::VectorXcd &lambda);
  /// df/dy at (t, y) and its eigenvalues (false: not computed).
  bool linearization(double t, const double *y, Eigen::MatrixXd &J,
                     Eigen::VectorXcd &lambda);
  Expected<bool> switchToBdf();

  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool adams_;
  bool autoChoice_;       // Adams that may move to BDF
  bool switched_ = false; // it did
  bool project_ = false;  // sga: onto the constraints after every step
  bool stepped_ = false;  // a step was taken: fixed start values are free
  bool afterEvent_ = false; // the next reinit continues after an event
  std::vector<int> heldAfterEvent_; // and holds these (reinit targets)
  std::string name_;
  SimStats saved_; // counters of earlier restarts
};

} // namespace ldae::runtime
