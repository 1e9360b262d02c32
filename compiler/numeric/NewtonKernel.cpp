// The Newton iteration's order of operations and damping (NewtonKernel.h).
#include "numeric/NewtonKernel.h"

namespace ldae::numeric {

NewtonOutcome iterateNewton(NewtonSystem &system, const NewtonPolicy &policy) {
  for (int it = 0; it < policy.maxIterations; ++it) {
    if (!system.evaluate(it))
      return {NewtonEnd::EvaluationFailed, it};
    if (system.convergedBeforeStep())
      return {NewtonEnd::Converged, it};
    if (!system.solveStep(it))
      return {NewtonEnd::SolveFailed, it};
    double alpha = 1;
    for (;;) {
      TrialVerdict v = system.tryStep(alpha);
      if (v == TrialVerdict::Accept)
        break;
      if (v == TrialVerdict::Fail)
        return {NewtonEnd::EvaluationFailed, it};
      alpha /= 2;
      if (alpha < policy.smallestDamping) {
        system.restore();
        return {NewtonEnd::Stalled, it + 1};
      }
    }
    switch (system.afterStep(alpha)) {
    case StepVerdict::Converged:
      return {NewtonEnd::Converged, it};
    case StepVerdict::Stop:
      return {NewtonEnd::Stopped, it + 1};
    case StepVerdict::Continue:
      break;
    }
  }
  return {NewtonEnd::IterationLimit, policy.maxIterations};
}

} // namespace ldae::numeric
