// Gauss-Newton projection onto the constraints (see ConstraintProjection.h).
#include "integrators/ConstraintProjection.h"
#include "numeric/NewtonKernel.h"

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
/// Simplified Newton (the first linearization kept) while each correction
/// is at most this fraction of the previous one.
constexpr double kSimplifiedRate = 0.1;
/// The start may be far off (start values are guesses): damped, and more
/// iterations.
constexpr int kMaxStartIterations = 50;
constexpr double kSmallestDamping = 1.0 / 1024;
/// A constraint whose residual is below this fraction of its row's
/// largest nominal-scaled derivative counts as met by the start.
constexpr double kSatisfied = 1e-10;
/// The Cholesky factor's smallest diagonal entry relative to its largest
/// below which the normal equations are left for the complete orthogonal
/// decomposition (condition of the equilibrated rows above 1e6).
constexpr double kNormalMinPivot = 1e-6;
/// Relative pivot below which the free unknowns cannot meet the rest.
constexpr double kRankTolerance = 1e-10;

} // namespace

ConstraintProjection::ConstraintProjection(const ModelEval &ev)
    : ev_(ev), n_(ev.n()),
      m_(ev.model().constraints && ev.model().constraint_jacobian
             ? ev.model().n_constraints
             : 0),
      c_(std::max(m_, 0)), jc_(size_t(std::max(m_, 0)) * ev.n()),
      noneHeld_(ev.n(), 0), fixedHeld_(ev.n(), 0), scale_(ev.n()) {
  const ldae_model &m = ev.model();
  for (int i = 0; i < n_; ++i) {
    scale_(i) = m.nominal ? m.nominal[i] : 1.0;
    fixedHeld_[i] = m.fixed && m.fixed[i] != 0;
  }
}

const std::vector<char> &
ConstraintProjection::fixedMask(bool holdFixed) const {
  return holdFixed ? fixedHeld_ : noneHeld_;
}

int ConstraintProjection::linearize(double t, const double *y,
                                    const std::vector<char> &held) {
  const ldae_model &m = ev_.model();
  if (int rc = m.constraint_jacobian(t, y, ev_.params(), jc_.data()))
    return rc;
  Jc_ = Eigen::Map<const Eigen::MatrixXd>(jc_.data(), m_, n_);
  A_ = Jc_ * scale_.asDiagonal();
  for (int i = 0; i < n_; ++i)
    if (held[i])
      A_.col(i).setZero();
  // Rows equilibrated to unit max norm first: a row's scale is its
  // constraint's units, which change neither the solution set nor, for
  // consistent rows, the least-norm solution, but do change which rows a
  // rank decision relative to the largest entry keeps. Unequilibrated,
  // Andrews' acceleration constraints (terms near 1e9) left its loop
  // closures (entries near 0.03) below the decomposition's threshold:
  // Gauss-Newton's corrections vanished with loop closures 1e-7 off.
  // Full row rank (every P_f met so far): the least-norm solution from
  // the normal equations, Cholesky of an m x m product (the 50-link
  // chain's 150 x 250 complete orthogonal decomposition was half of its
  // run); rank-deficient (redundant constraints) or ill-conditioned: the
  // complete orthogonal decomposition.
  rowScale_ = A_.rowwise().lpNorm<Eigen::Infinity>();
  normal_ = rowScale_.minCoeff() > 0;
  rowScale_ = rowScale_.unaryExpr([](double r) { return r > 0 ? 1 / r : 1.0; });
  As_ = rowScale_.asDiagonal() * A_;
  if (normal_) {
    llt_.compute(As_ * As_.transpose());
    const auto d = llt_.matrixLLT().diagonal();
    normal_ = llt_.info() == Eigen::Success &&
              d.minCoeff() > kNormalMinPivot * d.maxCoeff();
  }
  if (!normal_)
    cod_.compute(As_);
  return 0;
}

Eigen::VectorXd ConstraintProjection::leastNorm(const Eigen::VectorXd &b) const {
  if (normal_)
    return As_.transpose() * llt_.solve(rowScale_.cwiseProduct(b));
  return cod_.solve(rowScale_.cwiseProduct(b));
}

namespace {

/// What both projections' steps share: the point moved from where it was
/// by alpha times the step, back there when no damping is accepted, and
/// the model's code of the last failed evaluation.
struct ProjectionStep : numeric::NewtonSystem {
  ProjectionStep(double *y, int n) : yv(y, n) {}
  void restore() override { yv = from; }
  /// The code of the projection's end (ConstraintProjection.h).
  int status(const numeric::NewtonOutcome &out) const {
    switch (out.end) {
    case numeric::NewtonEnd::Converged:
      return 0;
    case numeric::NewtonEnd::EvaluationFailed:
    case numeric::NewtonEnd::SolveFailed:
      return rc;
    case numeric::NewtonEnd::Stalled:
      return rc ? rc : ConstraintProjection::kNoConvergence;
    default:
      return ConstraintProjection::kNoConvergence;
    }
  }

  Eigen::Map<Eigen::VectorXd> yv;
  Eigen::VectorXd from, step;
  double size = 0; ///< the step's max norm (nominal units)
  double norm = 0; ///< max |c| before the step
  int rc = 0;
};

} // namespace

int ConstraintProjection::iterate(double t, double *y,
                                  const std::vector<char> &held, double *dy,
                                  int maxIterations, bool damped) {
  const ldae_model &m = ev_.model();
  if (int rc = m.constraints(t, y, ev_.params(), c_.data()))
    return rc;
  struct Steps : ProjectionStep {
    Steps(ConstraintProjection &p, double t, double *y,
          const std::vector<char> &held, double *dy, bool damped)
        : ProjectionStep(y, p.n_), p(p), t(t), y(y), held(held), dy(dy),
          damped(damped), c(p.c_.data(), p.m_) {}
    bool evaluate(int it) override {
      // A start off P_f may be far from it: relinearized at every
      // iterate. A step's drift is of the order of its local error: the
      // first linearization serves while each correction is a tenth of
      // the last (the 50-link chain's output rows spent 40% of the run
      // relinearizing).
      fresh = damped || it == 0;
      return !(fresh && (rc = p.linearize(t, y, held)));
    }
    bool solveStep(int) override {
      Eigen::VectorXd z = p.leastNorm(-c);
      size = z.lpNorm<Eigen::Infinity>();
      if (!std::isfinite(size))
        return noConvergence();
      if (!fresh && size > kSimplifiedRate * last) {
        if ((rc = p.linearize(t, y, held)))
          return false;
        z = p.leastNorm(-c);
        size = z.lpNorm<Eigen::Infinity>();
        if (!std::isfinite(size))
          return noConvergence();
      }
      last = size;
      step = p.scale_.cwiseProduct(z);
      norm = c.lpNorm<Eigen::Infinity>();
      from = yv;
      return true;
    }
    numeric::TrialVerdict tryStep(double alpha) override {
      yv = from + alpha * step;
      rc = p.ev_.model().constraints(t, y, p.ev_.params(), p.c_.data());
      if (!damped && rc)
        return numeric::TrialVerdict::Fail;
      // Full steps near the manifold (quadratic convergence, and a
      // residual already at round-off need not decrease); halved where
      // the linearization overshoots.
      if (!damped || (rc == 0 && (c.lpNorm<Eigen::Infinity>() < norm ||
                                  alpha * size <= kConverged)))
        return numeric::TrialVerdict::Accept;
      return numeric::TrialVerdict::Reject;
    }
    numeric::StepVerdict afterStep(double alpha) override {
      if (dy)
        Eigen::Map<Eigen::VectorXd>(dy, p.n_) += alpha * step;
      double ref = std::max(
          1.0, yv.cwiseQuotient(p.scale_).lpNorm<Eigen::Infinity>());
      return alpha * size <= kConverged * ref ? numeric::StepVerdict::Converged
                                              : numeric::StepVerdict::Continue;
    }
    bool noConvergence() {
      rc = kNoConvergence;
      return false;
    }

    ConstraintProjection &p;
    double t;
    double *y;
    const std::vector<char> &held;
    double *dy;
    bool damped, fresh = true;
    Eigen::Map<const Eigen::VectorXd> c;
    double last = 0; // the previous correction's size
  } steps(*this, t, y, held, dy, damped);
  return steps.status(
      numeric::iterateNewton(steps, {maxIterations, kSmallestDamping}));
}

int ConstraintProjection::project(double t, double *y, bool holdFixed,
                                  double *dy) {
  if (dy)
    std::fill(dy, dy + n_, 0.0);
  if (m_ == 0)
    return 0;
  ++count_;
  return iterate(t, y, fixedMask(holdFixed), dy, kMaxIterations, false);
}

int ConstraintProjection::projectStart(double t, double *y, bool holdFixed,
                                       bool *restricted) {
  return projectStartHolding(t, y, fixedMask(holdFixed), restricted);
}

int ConstraintProjection::projectStartHolding(double t, double *y,
                                              const std::vector<char> &held,
                                              bool *restricted) {
  if (restricted)
    *restricted = false;
  if (m_ == 0)
    return 0;
  ++count_;
  if (int rc = ev_.model().constraints(t, y, ev_.params(), c_.data()))
    return rc;
  if (int rc = linearize(t, y, held))
    return rc;
  // A constraint the start already meets (to 1e-10 of what its row moves
  // per nominal unit) keeps every unknown it reads: the chain's positions
  // and velocities at rest stay, only its tensions (read by the third
  // generation alone) are solved. Without the rule the least-norm step
  // turned the 3-link chain's first link by 40 degrees. A constraint met
  // by chance (the chain's middle tension rows at equal start tensions)
  // must not keep what the others need: met constraints are released,
  // the latest first (the constraints come in generations), until the
  // rest have full rank in the unknowns left free.
  std::vector<char> met(m_, 0);
  for (int i = 0; i < m_; ++i)
    met[i] = std::fabs(c_[i]) <= kSatisfied * A_.row(i).lpNorm<Eigen::Infinity>();
  std::vector<char> keep;
  for (int last = m_ - 1;; --last) {
    keep = held;
    for (int i = 0; i < m_; ++i)
      for (int j = 0; met[i] && j < n_; ++j)
        if (A_(i, j) != 0)
          keep[j] = 1;
    if (freeRankFull(met, keep))
      break;
    while (last >= 0 && !met[last])
      --last;
    if (last < 0)
      break;
    met[last] = 0;
  }
  std::vector<double> y0(y, y + n_);
  if (keep != held) {
    if (iterate(t, y, keep, nullptr, kMaxStartIterations, true) == 0) {
      if (restricted)
        *restricted = true;
      return 0;
    }
    std::copy(y0.begin(), y0.end(), y);
  }
  return iterate(t, y, held, nullptr, kMaxStartIterations, true);
}

int ConstraintProjection::projectAlong(double t, double *y,
                                       const Eigen::MatrixXd &T) {
  if (m_ == 0)
    return 0;
  ++count_;
  const ldae_model &m = ev_.model();
  if (int rc = m.constraints(t, y, ev_.params(), c_.data()))
    return rc;
  struct Steps : ProjectionStep {
    Steps(ConstraintProjection &p, double t, double *y,
          const Eigen::MatrixXd &T)
        : ProjectionStep(y, p.n_), p(p), t(t), y(y), T(T),
          c(p.c_.data(), p.m_),
          ref(std::max(1.0,
                       yv.cwiseQuotient(p.scale_).lpNorm<Eigen::Infinity>())) {
    }
    bool evaluate(int) override {
      const ldae_model &m = p.ev_.model();
      return !(rc = m.constraint_jacobian(t, y, p.ev_.params(), p.jc_.data()));
    }
    bool solveStep(int) override {
      Eigen::MatrixXd B =
          Eigen::Map<const Eigen::MatrixXd>(p.jc_.data(), p.m_, p.n_) * T;
      // Rows equilibrated as in linearize: a rank decision relative to the
      // largest entry must not drop a constraint for its units.
      Eigen::VectorXd rs = B.rowwise().lpNorm<Eigen::Infinity>();
      rs = rs.unaryExpr([](double r) { return r > 0 ? 1 / r : 1.0; });
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(
          rs.asDiagonal() * B);
      cod.setThreshold(kRankTolerance);
      step = T * cod.solve(rs.cwiseProduct(-c));
      size = step.cwiseQuotient(p.scale_).lpNorm<Eigen::Infinity>();
      if (!std::isfinite(size)) {
        rc = kNoConvergence;
        return false;
      }
      norm = c.lpNorm<Eigen::Infinity>();
      from = yv;
      return true;
    }
    numeric::TrialVerdict tryStep(double alpha) override {
      yv = from + alpha * step;
      rc = p.ev_.model().constraints(t, y, p.ev_.params(), p.c_.data());
      if (rc == 0 && (c.lpNorm<Eigen::Infinity>() < norm ||
                      alpha * size <= kConverged * ref))
        return numeric::TrialVerdict::Accept;
      return numeric::TrialVerdict::Reject;
    }
    numeric::StepVerdict afterStep(double alpha) override {
      return alpha * size <= kConverged * ref ? numeric::StepVerdict::Converged
                                              : numeric::StepVerdict::Continue;
    }

    ConstraintProjection &p;
    double t;
    double *y;
    const Eigen::MatrixXd &T;
    Eigen::Map<const Eigen::VectorXd> c;
    const double ref;
  } steps(*this, t, y, T);
  return steps.status(
      numeric::iterateNewton(steps, {kMaxStartIterations, kSmallestDamping}));
}

int ConstraintProjection::projectHolding(double t, double *y,
                                         const std::vector<int> &held) {
  std::vector<char> mask(n_, 0);
  for (int i : held)
    if (i >= 0 && i < n_)
      mask[i] = 1;
  return projectStartHolding(t, y, mask, nullptr);
}

bool ConstraintProjection::freeRankFull(const std::vector<char> &met,
                                        const std::vector<char> &keep) const {
  std::vector<int> rows, cols;
  for (int i = 0; i < m_; ++i)
    if (!met[i])
      rows.push_back(i);
  for (int j = 0; j < n_; ++j)
    if (!keep[j])
      cols.push_back(j);
  if (rows.empty())
    return true;
  if (cols.size() < rows.size())
    return false;
  Eigen::MatrixXd B(rows.size(), cols.size());
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t k = 0; k < cols.size(); ++k)
      B(r, k) = A_(rows[r], cols[k]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(B);
  qr.setThreshold(kRankTolerance);
  return qr.rank() == Eigen::Index(rows.size());
}

int ConstraintProjection::correction(double t, const double *y, double *dy) {
  Eigen::Map<Eigen::VectorXd> d(dy, n_);
  d.setZero();
  if (m_ == 0)
    return 0;
  if (int rc = ev_.model().constraints(t, y, ev_.params(), c_.data()))
    return rc;
  if (int rc = linearize(t, y, noneHeld_))
    return rc;
  d = scale_.cwiseProduct(
      leastNorm(-Eigen::Map<const Eigen::VectorXd>(c_.data(), m_)));
  return 0;
}

void ConstraintProjection::projectError(double *err) const {
  if (m_ == 0)
    return;
  Eigen::Map<Eigen::VectorXd> e(err, n_);
  Eigen::VectorXd z = leastNorm(Jc_ * e);
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
