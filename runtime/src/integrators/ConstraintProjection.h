// Projection onto the constraint manifold {c(t, y) = 0} of a model with
// geometric slots (ldae_model::constraints, constraint_jacobian; `--method
// sga|ode`): Gauss-Newton, each correction the minimum-norm solution of
// Jc dy = -c in the nominal-scaled unknowns (dy = D z, least ||z||; a
// complete orthogonal decomposition, so redundant constraints are fine).
// The one projection of every step (CVODE's projection function), of
// interpolated output rows, and of Adams restarts; the start (and a restart
// after an event) by projectStart, which keeps what the start values
// already satisfy.
#pragma once

#include "model/ModelEval.h"

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
  /// The start's projection (seed 002's rule for mechanical systems: the
  /// positions and velocities of a consistent start stay, the multipliers
  /// jump): the unknowns read by no constraint that y already satisfies
  /// move, by damped Gauss-Newton on every constraint; where that has no
  /// solution, project() over all unknowns. `restricted` (may be null)
  /// says which rule gave the point.
  int projectStart(double t, double *y, bool holdFixed,
                   bool *restricted = nullptr);
  /// An event's re-initialization (seed 002): y moves only along the
  /// columns of T (the jump directions of the model as written), to the
  /// point y + T a on the constraints, by damped Gauss-Newton on a with
  /// least-norm steps. kNoConvergence where no such point is found (the
  /// constraints cannot be met along T).
  int projectAlong(double t, double *y, const Eigen::MatrixXd &T);
  /// projectStart's rule with the unknowns `held` kept instead of the
  /// fixed ones: the jump rule's fallback after an event where holding the
  /// reinit targets leaves no step along T (a pendulum's vx reinit at a
  /// wall: its position, which a met constraint reads, stays; vy moves).
  int projectHolding(double t, double *y, const std::vector<int> &held);
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
  int projectStartHolding(double t, double *y, const std::vector<char> &held,
                          bool *restricted);
  int linearize(double t, const double *y, const std::vector<char> &held);
  /// Gauss-Newton from y over the unknowns not `held`, each step halved
  /// until max |c| decreases (a start may be far off).
  int iterate(double t, double *y, const std::vector<char> &held,
              double *dy, int maxIterations, bool damped);
  const std::vector<char> &fixedMask(bool holdFixed) const;
  /// The least-norm z with A_ z = b (A_ as last linearized).
  Eigen::VectorXd leastNorm(const Eigen::VectorXd &b) const;
  /// Whether the constraints not `met` have full row rank in the unknowns
  /// not kept (A_ at the start point).
  bool freeRankFull(const std::vector<char> &met,
                    const std::vector<char> &keep) const;

  const ModelEval &ev_;
  int n_, m_;
  std::vector<double> c_, jc_;
  /// The masks of held unknowns: none (the stabilized field's correction
  /// at every f evaluation, the projection after each step) and those
  /// with a fixed start value (the start).
  std::vector<char> noneHeld_, fixedHeld_;
  Eigen::VectorXd scale_;
  Eigen::MatrixXd Jc_, A_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  /// The normal-equations path of linearize: rows of A_ scaled to unit
  /// max norm (As_), the Cholesky factors of As_ As_^T.
  bool normal_ = false;
  Eigen::VectorXd rowScale_;
  Eigen::MatrixXd As_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  long count_ = 0;
};

} // namespace ldae::runtime
