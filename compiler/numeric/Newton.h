// Newton and Gauss–Newton iteration on a residual given as a callback, with
// the Jacobian from a callback or by forward differences, for the
// compiler's passes (is a set of start conditions solvable?). Its loop is
// the one Newton kernel (NewtonKernel.h) that the runtime's initialization
// and constraint projection also run on; knows nothing of the IR or of
// ldae_model.
//
// Each step is the minimum-norm least-squares solution of J dx = -r (a
// complete orthogonal decomposition), so the same iteration serves square,
// over- and under-determined systems: for a square nonsingular J it is
// Newton's method, otherwise Gauss–Newton.
#pragma once

#include <Eigen/Dense>

#include <functional>

namespace ldae::numeric {

/// r = F(x); false when F cannot be evaluated at x (a domain error).
using ResidualFn =
    std::function<bool(const Eigen::VectorXd &x, Eigen::VectorXd &r)>;
/// J = dF/dx at x; false when it cannot be evaluated.
using JacobianFn =
    std::function<bool(const Eigen::VectorXd &x, Eigen::MatrixXd &J)>;

/// Forward-difference Jacobian of `f` at `x` given r0 = F(x): column k
/// uses the step h_k = relStep * max(1, |x_k|). False when F fails at a
/// perturbed point.
bool finiteDifferenceJacobian(const ResidualFn &f, const Eigen::VectorXd &x,
                              const Eigen::VectorXd &r0, Eigen::MatrixXd &J,
                              double relStep = 1e-7);

struct NewtonOptions {
  int maxIterations = 50;
  /// Converged when max |r_i| < tolerance * max(1, max |x_k|): residuals
  /// judged in the units of the unknowns.
  double tolerance = 1e-9;
  /// Forward-difference step (relative) when no Jacobian callback is given.
  double fdStep = 1e-7;
  /// Rank threshold of the least-squares solve (relative to the largest
  /// pivot of the decomposition); 0: Eigen's default.
  double rankThreshold = 0;
  /// Halve a step (up to 30 times) until the residual's 2-norm decreases:
  /// for starts far from the solution set (the SGA's random points on
  /// trigonometric constraints), where full steps diverge. When no halving
  /// decreases it, the iteration stops there (NotConverged).
  bool backtrack = false;
};

enum class NewtonStatus {
  Converged,
  NotConverged,   ///< iteration limit reached
  EvaluationFailed, ///< F or J could not be evaluated, or is not finite
};

struct NewtonResult {
  NewtonStatus status = NewtonStatus::NotConverged;
  int iterations = 0;
  double residualNorm = 0; ///< max |r_i| at the last evaluation
  bool converged() const { return status == NewtonStatus::Converged; }
};

/// Iterates x in place from its value on entry. `jacobian` may be empty:
/// forward differences then.
NewtonResult gaussNewton(const ResidualFn &f, const JacobianFn &jacobian,
                         Eigen::VectorXd &x, const NewtonOptions &opts = {});

} // namespace ldae::numeric
