// The one Newton iteration of ldaec: evaluate at the iterate, test for
// convergence, solve the linearization for a step, take it (halved while
// the system rejects it), test again. The system behind it is an
// interface (NewtonSystem) so that each user keeps its own residual,
// linear solve (dense least squares, KLU, a reused factorization) and
// convergence test, and its exact numbers; the kernel owns the order of
// those operations, the iteration limit and the damping.
//
// Users: gaussNewton (Newton.h, the compiler's passes), the runtime's
// initialization (dense along the jump space, sparse with KLU) and the
// SGA's constraint projection. Knows nothing of the IR or of ldae_model.
#pragma once

namespace ldae::numeric {

/// What the system says of a trial step.
enum class TrialVerdict {
  Accept, ///< keep it
  Reject, ///< halve it (a damped iteration) and try again
  Fail,   ///< the iteration cannot go on (an evaluation failed)
};

/// What the system says after a step.
enum class StepVerdict {
  Continue,  ///< iterate again
  Converged, ///< the iterate is the solution
  Stop,      ///< no further step helps (the caller knows why)
};

/// A system the kernel iterates on. The iterate is the system's own; the
/// kernel calls, per iteration and in this order: evaluate,
/// convergedBeforeStep, solveStep, tryStep (from alpha = 1, halved on
/// Reject), afterStep.
class NewtonSystem {
public:
  virtual ~NewtonSystem() = default;
  /// Evaluates at the current iterate what the test and the step need
  /// (residual, Jacobian); false when it cannot.
  virtual bool evaluate(int iteration) = 0;
  /// Whether the iterate just evaluated is already the solution.
  virtual bool convergedBeforeStep() { return false; }
  /// Solves the linearization for the step; false when it cannot.
  virtual bool solveStep(int iteration) = 0;
  /// Moves the iterate to where it was before the step plus `alpha` times
  /// the step.
  virtual TrialVerdict tryStep(double alpha) = 0;
  /// Moves the iterate back to where it was before the step: no damping
  /// was accepted.
  virtual void restore() {}
  /// After the step of `alpha` was taken.
  virtual StepVerdict afterStep(double alpha) = 0;
};

/// The iteration limit and the damping.
struct NewtonPolicy {
  int maxIterations = 50;
  /// A rejected step is halved until its factor falls below this; 1: full
  /// steps only (a rejection stalls the iteration at once).
  double smallestDamping = 1;
};

enum class NewtonEnd {
  Converged,        ///< convergedBeforeStep or afterStep said so
  IterationLimit,   ///< maxIterations steps without convergence
  Stalled,          ///< no damping of a step was accepted (iterate restored)
  Stopped,          ///< afterStep said Stop
  EvaluationFailed, ///< evaluate returned false or a trial said Fail
  SolveFailed,      ///< solveStep returned false
};

struct NewtonOutcome {
  NewtonEnd end = NewtonEnd::IterationLimit;
  /// The iteration it ended in (0-based); one past it when it stalled or
  /// stopped after a step; maxIterations at the limit.
  int iterations = 0;
};

/// Iterates `system` under `policy`.
NewtonOutcome iterateNewton(NewtonSystem &system, const NewtonPolicy &policy);

} // namespace ldae::numeric
