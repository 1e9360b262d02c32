// Gauss-Newton projection onto the constraints (see ConstraintProjection.h).
#include "ConstraintProjection.h"

#include <algorithm>
#include <cmath>

namespace ldae::runtime {

namespace {

/// Gauss-Newton converges quadratically from a point near the manifold
/// (a step's drift is of the order of its local error); more iterations
/// than this mean the point is too far off, and a smaller step helps.
constexpr int kMaxIterations = 12;
/// A correction below this (in nominal units, relative to the point) is
/// round-off: the point is on the manifold.
constexpr double kConverged = 1e-14;

} // namespace

ConstraintProjection::ConstraintProjection(const ModelEval &ev)
    : ev_(ev), n_(ev.n()),
      m_(ev.model().constraints && ev.model().constraint_jacobian
             ? ev.model().n_constraints
             : 0),
      c_(std::max(m_, 0)), jc_(size_t(std::max(m_, 0)) * ev.n()),
      scale_(ev.n()) {
  for (int i = 0; i < n_; ++i)
    scale_(i) = ev.model().nominal ? ev.model().nominal[i] : 1.0;
}

int ConstraintProjection::linearize(double t, const double *y,
                                    bool holdFixed) {
  const ldae_model &m = ev_.model();
  if (int rc = m.constraint_jacobian(t, y, ev_.params(), jc_.data()))
    return rc;
  Jc_ = Eigen::Map<const Eigen::MatrixXd>(jc_.data(), m_, n_);
  A_ = Jc_ * scale_.asDiagonal();
  if (holdFixed && m.fixed)
    for (int i = 0; i < n_; ++i)
      if (m.fixed[i])
        A_.col(i).setZero();
  cod_.compute(A_);
  return 0;
}

int ConstraintProjection::project(double t, double *y, bool holdFixed,
                                  double *dy) {
  if (dy)
    std::fill(dy, dy + n_, 0.0);
  if (m_ == 0)
    return 0;
  ++count_;
  const ldae_model &m = ev_.model();
  Eigen::Map<Eigen::VectorXd> yv(y, n_);
  for (int it = 0; it < kMaxIterations; ++it) {
    if (int rc = m.constraints(t, y, ev_.params(), c_.data()))
      return rc;
    // Relinearized at every iterate: a start off P_f may be far from it
    // (a step's drift needs one or two iterations either way).
    if (int rc = linearize(t, y, holdFixed))
      return rc;
    Eigen::VectorXd z =
        cod_.solve(-Eigen::Map<const Eigen::VectorXd>(c_.data(), m_));
    Eigen::VectorXd step = scale_.cwiseProduct(z);
    yv += step;
    if (dy)
      Eigen::Map<Eigen::VectorXd>(dy, n_) += step;
    double size = z.lpNorm<Eigen::Infinity>();
    double ref = std::max(1.0, yv.cwiseQuotient(scale_).lpNorm<Eigen::Infinity>());
    if (!std::isfinite(size))
      return kNoConvergence;
    if (size <= kConverged * ref)
      return 0;
  }
  return kNoConvergence;
}

int ConstraintProjection::correction(double t, const double *y, double *dy) {
  Eigen::Map<Eigen::VectorXd> d(dy, n_);
  d.setZero();
  if (m_ == 0)
    return 0;
  if (int rc = ev_.model().constraints(t, y, ev_.params(), c_.data()))
    return rc;
  if (int rc = linearize(t, y, false))
    return rc;
  d = scale_.cwiseProduct(
      cod_.solve(-Eigen::Map<const Eigen::VectorXd>(c_.data(), m_)));
  return 0;
}

void ConstraintProjection::projectError(double *err) const {
  if (m_ == 0)
    return;
  Eigen::Map<Eigen::VectorXd> e(err, n_);
  Eigen::VectorXd z = cod_.solve(Jc_ * e);
  e -= scale_.cwiseProduct(z);
}

int ConstraintProjection::largestResidual(double t, const double *y,
                                          double &value) {
  value = 0;
  if (m_ == 0)
    return 0;
  if (int rc = ev_.model().constraints(t, y, ev_.params(), c_.data()))
    return rc;
  for (double c : c_)
    value = std::max(value, std::fabs(c));
  return 0;
}

} // namespace ldae::runtime
