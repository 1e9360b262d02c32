// The method-neutral face of a SUNDIALS integrator: what the run loop
// (Simulator.cpp), the initialization and the failure report need from IDA
// or CVODE, and nothing that names either. IdaIntegrator and
// CvodeIntegrator implement it; makeIntegrator picks one.
#pragma once

#include "integrators/ErrorWeights.h"
#include "model/ModelEval.h"
#include "ldae/Simulation.h"
#include "support/Expected.h"

#include <memory>
#include <string>
#include <vector>

namespace ldae::runtime {

/// How far ahead of t a one-step call's `tout` may point, relative to
/// 1 + |t|.
inline constexpr double kFirstStepHorizon = 1e12;

/// The `tout` of a one-step call from t towards tstop. SUNDIALS reads it
/// only on the first call after a (re)start, for the scale of its first
/// step, whose lower bound is 100 u max(|t|, |tout|): `--stop 1e300` made
/// that 2e286 and the first step failed at t = 0. A span beyond the
/// horizon is taken as the horizon (the step size grows from there).
inline double oneStepTarget(double t, double tstop) {
  double reach = kFirstStepHorizon * (1 + (t < 0 ? -t : t));
  return tstop - t > reach ? t + reach : tstop;
}

/// Why a step or a start failed, in terms of the failure report (each
/// integrator maps its own return codes onto these).
enum class FailureKind {
  TooMuchWork,     // too many steps without reaching the target
  TooMuchAccuracy, // the tolerances cannot be met
  ErrorTest,       // the error test failed with the smallest step
  Convergence,     // the nonlinear iteration failed repeatedly
  LinearSetup,     // the iteration matrix is singular
  LinearSolve,
  Domain,        // an equation left its domain and smaller steps did not help
  RootFunction,  // an event condition could not be evaluated
  NoStart,       // no consistent initial point
  StepCollapsed, // our own: steps at round-off level while the solver goes on
  Overflow,      // the trial points or their derivatives were not finite
  Other,
};

/// The outcome of one internal step (or of a start computation).
struct StepStatus {
  enum Kind { Step, StopReached, Root, Failed } kind = Step;
  FailureKind failure = FailureKind::Other;
  std::string code; ///< the solver's own name of the failure ("IDA_ERR_FAIL")

  bool ok() const { return kind != Failed; }
  static StepStatus failed(FailureKind f, std::string code) {
    return {Failed, f, std::move(code)};
  }
};

class Integrator {
public:
  explicit Integrator(const ModelEval &ev) : ev_(ev) {}
  virtual ~Integrator() = default;
  Integrator(const Integrator &) = delete;
  Integrator &operator=(const Integrator &) = delete;

  /// "IDA", "CVODE (BDF)" or "CVODE (Adams)".
  virtual const char *name() const = 0;

  /// Makes the local error test use `weights` (kept; null: rtol and atol
  /// alone). Before init.
  void weighErrors(ErrorWeights *weights) { shared_.weights = weights; }
  /// Creates the integrator at (t0, y, y') for state set `set`; `atol` per
  /// unknown; `errorTestAlgebraic`: whether algebraic unknowns are in the
  /// local error test (an ODE has none). Errors are internal (a SUNDIALS
  /// call failed).
  virtual Expected<bool> init(int set, double t0, const double *y,
                              const double *yp, double rtol,
                              const std::vector<double> &atol, double tstop,
                              bool errorTestAlgebraic) = 0;
  /// Restarts at (t, y, y') with state set `set`.
  virtual Expected<bool> reinit(int set, double t, const double *y,
                                const double *yp) = 0;
  /// The next reinit continues the run after an event (also in a new
  /// mode's integrator): a projecting integrator re-initializes by the jump
  /// rule there, not by the start's, holding `held` (the fired reinits'
  /// targets) instead of the fixed start values.
  virtual void nextReinitAfterEvent(const std::vector<int> &held) {
    (void)held;
  }
  /// Completes the held point from its differential values: y' of the
  /// differential and y of the algebraic unknowns (IDACalcIC; for an ODE
  /// y' = f(t, y)). `tout1` is the first time the run will reach.
  virtual StepStatus completeStart(double tout1) = 0;
  /// The time no step may pass (the stop time, later time events).
  virtual Expected<bool> setStopTime(double tstop) = 0;
  /// The longest step (0: no limit), kept over restarts: root functions
  /// are only compared at step ends, so a relation that crosses and
  /// crosses back within one long step would be missed.
  virtual Expected<bool> setMaxStep(double hmax) = 0;
  /// One internal step towards the stop time.
  virtual StepStatus step(double &tret) = 0;
  /// y and y' at t within the last step, from the interpolating polynomial
  /// (y' of an ODE from its right-hand side at the interpolated y).
  virtual Expected<bool> interpolate(double t, double *y, double *yp) = 0;

  /// The current solution (after step, completeStart or reinit).
  virtual const double *y() const = 0;
  virtual const double *yp() const = 0;
  /// The set whose residual is integrated.
  int set() const { return shared_.set; }
  /// KLU (true) or dense LU.
  bool sparse() const { return sparse_; }

  /// Adds this integrator's counters (all restarts) into `stats`.
  virtual void addCounters(SimStats &stats) const = 0;
  /// Root components that were found at the last root return.
  virtual std::vector<int> rootsFound() const = 0;
  /// Weighted local error of each unknown at the last (failed) step.
  virtual std::vector<double> weightedErrors() const = 0;
  /// Time the integrator reached (it may be past the last returned time).
  virtual double currentTime() const = 0;
  /// Size of the last successful step.
  virtual double lastStep() const = 0;
  /// The cj for which dF/dy + cj dF/dy' is (a multiple of) the current
  /// iteration matrix: IDA's cj, CVODE's 1/gamma.
  virtual double iterationCj() const = 0;
  /// The last message the solver wanted to print (we silence its printing).
  const std::string &solverMessage() const { return shared_.message; }

  /// Residual row of the last domain error (-1: none), and the unknowns
  /// there (null: none).
  int lastDomainRow() const { return shared_.domainRow; }
  const double *lastDomainY() const {
    return shared_.domainY.empty() ? nullptr : shared_.domainY.data();
  }

  /// What the C callbacks of either solver share.
  struct CallbackData {
    const ModelEval *ev = nullptr;
    int set = 0;
    int domainRow = -1;
    std::vector<double> domainY; // y where the domain error happened
    // CVODE: zeros for f = -F(t, y, 0), and a y' buffer for the roots.
    std::vector<double> zeros, work;
    std::string message;
    bool nonFinite = false; // a trial point was refused as not finite
    /// The error weights when computed variables raise them (null: the
    /// solvers' own from rtol and atol), and the time of the point the
    /// solvers ask them for (they pass only y; IDA's y' is `yp`).
    ErrorWeights *weights = nullptr;
    double t = 0;
    const double *yp = nullptr;
    std::vector<double> weightsYp; // CVODE: f(t, y) for the weights
  };

  /// Translates an ABI status into a SUNDIALS callback return, recording a
  /// domain error (rc > 0: recoverable, the solver retries with a smaller
  /// step; the failure report names the row).
  static int callbackStatus(CallbackData &d, int rc, const double *y);
  /// Whether v[0..n) is finite: a trial point that is not (overflow) must
  /// fail recoverably, for the solvers' step-size control has no guard
  /// against NaN and a NaN step size loops forever inside a solver call.
  static bool finite(const double *v, int n);

protected:
  /// A domain failure caused by a refused non-finite trial point is an
  /// overflow, not an equation leaving its domain.
  StepStatus overflowAware(StepStatus st) const {
    if (st.failure == FailureKind::Domain && shared_.nonFinite &&
        shared_.domainRow < 0)
      st.failure = FailureKind::Overflow;
    return st;
  }

  const ModelEval &ev_;
  CallbackData shared_;
  bool sparse_ = false;
};

/// The integrator the options ask for: `Auto` is CVODE (BDF) for an
/// explicit ODE (one state set, ldae_model::explicit_ode) whose error test
/// weighs no computed variable (`weighsComputed`: ErrorWeights propagate
/// and the algebraic error test is on), IDA otherwise. CVODE for a model
/// that is not an explicit ODE is an Error naming why.
Expected<std::unique_ptr<Integrator>>
makeIntegrator(const ModelEval &ev, IntegratorChoice choice,
               bool weighsComputed);

} // namespace ldae::runtime
