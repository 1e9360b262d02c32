// IDA for an ldae_model (see Integrator.h): SUNContext, serial vectors,
// tolerances scaled by the nominal values, the differential/algebraic id of
// the current state set, the dense or KLU linear solver with the model's
// Jacobian, root functions. Re-initialized in place when the state set
// changes; counters are summed across re-initializations.
#pragma once

#include "integrators/Integrator.h"

namespace ldae::runtime {

class IdaIntegrator final : public Integrator {
public:
  explicit IdaIntegrator(const ModelEval &ev);
  ~IdaIntegrator() override;

  const char *name() const override { return "IDA"; }
  Expected<bool> init(int set, double t0, const double *y, const double *yp,
                      double rtol, const std::vector<double> &atol,
                      double tstop, bool errorTestAlgebraic) override;
  Expected<bool> reinit(int set, double t, const double *y,
                        const double *yp) override;
  /// IDACalcIC(IDA_YA_YDP_INIT).
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
  Expected<bool> setupLinearSolver();
  Expected<bool> setupId();

  struct Impl;
  std::unique_ptr<Impl> impl_;
  SimStats saved_; // counters of earlier restarts
};

} // namespace ldae::runtime
