// Projection onto the constraint manifold {c(t, y) = 0} of a model with
// geometric slots (ldae_model::constraints, constraint_jacobian; `--method
// sga|ode`): Gauss-Newton, each correction the minimum-norm solution of
// Jc dy = -c in the nominal-scaled unknowns (dy = D z, least ||z||; a
// complete orthogonal decomposition, so redundant constraints are fine).
// The one projection of the start point, of every step (CVODE's
// projection function), of interpolated output rows, and of Adams restarts.
#pragma once

#include "ModelEval.h"

#include <Eigen/Dense>
#include <vector>

namespace ldae::runtime {

class ConstraintProjection {
public:
  explicit ConstraintProjection(const ModelEval &ev);

  /// Whether the model has constraints to project onto.
  bool active() const { return m_ > 0; }

  /// Moves y onto c(t, y) = 0. `holdFixed`: coordinates with a fixed start
  /// value do not move (the start's rule). `dy` (may be null) receives the
  /// total correction. Returns the ABI status of the evaluations (> 0: a
  /// domain error in constraint rc - 1), or kNoConvergence.
  int project(double t, double *y, bool holdFixed, double *dy = nullptr);
  /// One Gauss-Newton correction at y, not applied: dy = -D (Jc D)^+ c.
  int correction(double t, const double *y, double *dy);
  /// The component of `err` normal to the manifold at the last projected
  /// point removed: err -= D (Jc D)^+ Jc err (CVODE's error projection).
  void projectError(double *err) const;
  /// max_i |c_i(t, y)| (0 when there is none); the ABI status.
  int largestResidual(double t, const double *y, double &value);
  /// Projections done (start, steps, rows).
  long count() const { return count_; }

  static constexpr int kNoConvergence = 1 << 29;

private:
  int linearize(double t, const double *y, bool holdFixed);

  const ModelEval &ev_;
  int n_, m_;
  std::vector<double> c_, jc_;
  Eigen::VectorXd scale_;
  Eigen::MatrixXd Jc_, A_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  long count_ = 0;
};

} // namespace ldae::runtime
