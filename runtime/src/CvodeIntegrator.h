// CVODE for an explicit-ODE ldae_model (see Integrator.h and
// ldae_model::explicit_ode): y' = f(t, y) = -F(t, y, 0) and df/dy =
// -dF/dy, so the model's residual and Jacobian serve unchanged. BDF with
// Newton iteration and the dense or KLU solver for stiff models; Adams with
// fixed-point iteration (no Jacobian) for non-stiff ones.
#pragma once

#include "Integrator.h"

namespace ldae::runtime {

class CvodeIntegrator final : public Integrator {
public:
  CvodeIntegrator(const ModelEval &ev, bool adams);
  ~CvodeIntegrator() override;

  const char *name() const override {
    return adams_ ? "CVODE (Adams)" : "CVODE (BDF)";
  }
  Expected<bool> init(int set, double t0, const double *y, const double *yp,
                      double rtol, const std::vector<double> &atol,
                      double tstop, bool errorTestAlgebraic) override;
  Expected<bool> reinit(int set, double t, const double *y,
                        const double *yp) override;
  /// y' = f(t0, y): every unknown of an ODE is differential.
  StepStatus completeStart(double tout1) override;
  Expected<bool> setStopTime(double tstop) override;
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
  Expected<bool> setupSolver();

  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool adams_;
  SimStats saved_; // counters of earlier restarts
};

} // namespace ldae::runtime
