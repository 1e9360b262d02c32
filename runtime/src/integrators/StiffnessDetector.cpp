// The stiffness test of Adams under `--integrator auto` (see
// StiffnessDetector.h).
#include "integrators/StiffnessDetector.h"

#include <cmath>

namespace ldae::runtime {

bool StiffnessDetector::looksStiff(const Eigen::VectorXcd &lambda, double h,
                                   double rest) {
  // Stiff: Adams' step is held near its stability (and fixed-point
  // convergence) bound h |lambda| ~ 0.1-1 by a decaying mode, and the rest
  // of the run spans many of that mode's time constants. The bound is on
  // |lambda|, not on the decay rate: a lightly damped mode that rings out
  // (lambda = -50 +- 1000i) holds Adams at h ~ 1e-3 as firmly as a real
  // one at -1000. An undamped one never decays: it stays Adams' to follow.
  for (Eigen::Index i = 0; i < lambda.size(); ++i)
    if (std::abs(lambda[i]) * h >= 0.1 && -lambda[i].real() * rest >= 1e3)
      return true;
  return false;
}

} // namespace ldae::runtime
