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
//
// This class is the CVODE wrapper: when it projects and restarts. Where the
// point goes and the Adams stabilization are SgaProjectionPolicy's; when
// Adams is stiff, StiffnessDetector's.
#pragma once

#include "integrators/Integrator.h"
#include "integrators/SgaProjectionPolicy.h"

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
  /// The field CVODE integrates (the stabilized one under Adams).
  SgaProjectionPolicy::Field field();
  /// y onto the constraints by the start's rule (fixed start values held
  /// before the first step), and the Adams stabilization rate there.
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
