// f and df/dy of a linearly implicit model (see ImplicitOde.h).
#include "integrators/ImplicitOde.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace ldae::runtime {

namespace {

/// E = dF/dy' comes from the iteration matrix dF/dy + cj dF/dy' at two
/// values of cj: (J(c) - J(0)) / c. An entry with both parts is rounded to
/// eps |dy + c dyp|, so E's entry carries eps (1 + |dy| / (c |dyp|)); a large
/// power of two keeps that near eps whatever |dF/dy| is (with c = 1 a
/// stiff row's dF/dy of 1e8 against dF/dy' of 1 would leave E 1e-8
/// accurate), and dividing by it is exact.
constexpr double kEScale = 1048576.0; // 2^20

/// Below this reciprocal condition number of the equilibrated dF/dy'
/// (every row's and then every column's largest entry scaled to [1, 2))
/// it counts as singular. Equilibrated, the number no longer depends on
/// units: Andrews' squeezer mixes moments of inertia of 1e-6 with
/// tangency rows of products near 1e9, and its E, well posed, had an
/// unscaled reciprocal condition far below any threshold. Its entries are
/// accurate to about eps (see kEScale), so the solve's relative error is
/// about eps / rcond: at 1e-13 that is 2e-3, no digit a tolerance could
/// ask for, and below it the matrix is within a few hundred roundings of
/// a singular one.
constexpr double kMinRcond = 1e-13;

/// The power of two that brings `largest` into [1, 2): scaling by it is
/// exact.
double unitScale(double largest) { return std::ldexp(1.0, -std::ilogb(largest)); }

} // namespace

ImplicitOde::ImplicitOde(const ModelEval &ev)
    : ev_(ev), n_(ev.n()), zeros_(ev.n(), 0.0), r_(ev.n()), yAt_(ev.n()) {}

int ImplicitOde::factor(double t, const double *y) {
  if (factored_ && t == tAt_ && std::equal(y, y + n_, yAt_.begin()))
    return 0;
  factored_ = false;
  const double *yp = zeros_.data();
  if (int rc = ev_.jacobian(0, t, y, yp, 0.0, J0_))
    return rc;
  if (int rc = ev_.jacobian(0, t, y, yp, kEScale, Jc_))
    return rc;
  Jc_ -= J0_;
  Jc_ /= kEScale;
  // Rows first (a row's units are its equation's), then columns (an
  // unknown's): R E C, whose LU also solves more accurately than E's.
  rowScale_ = Jc_.rowwise().lpNorm<Eigen::Infinity>();
  if (!(rowScale_.minCoeff() > 0) || !rowScale_.allFinite())
    return kSingular;
  rowScale_ = rowScale_.unaryExpr(&unitScale);
  Jc_ = rowScale_.asDiagonal() * Jc_;
  colScale_ = Jc_.colwise().lpNorm<Eigen::Infinity>().transpose();
  if (!(colScale_.minCoeff() > 0))
    return kSingular;
  colScale_ = colScale_.unaryExpr(&unitScale);
  Jc_ = Jc_ * colScale_.asDiagonal();
  lu_.compute(Jc_);
  if (!(lu_.rcond() >= kMinRcond))
    return kSingular;
  tAt_ = t;
  std::copy(y, y + n_, yAt_.begin());
  factored_ = true;
  return 0;
}

int ImplicitOde::rhs(double t, const double *y, double *f) {
  if (int rc = ev_.residual(0, t, y, zeros_.data(), r_.data()))
    return rc;
  if (int rc = factor(t, y))
    return rc;
  // E f = -F  <=>  (R E C) (C^-1 f) = -R F.
  Eigen::Map<Eigen::VectorXd>(f, n_) = -colScale_.cwiseProduct(lu_.solve(
      rowScale_.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(r_.data(), n_))));
  return 0;
}

int ImplicitOde::jacobian(double t, const double *y, const double *f,
                          double *J) {
  if (int rc = factor(t, y))
    return rc;
  // dF/dy at y' = f (J0_ is free again: factor() is done with it).
  if (int rc = ev_.jacobian(0, t, y, f, 0.0, J0_))
    return rc;
  Eigen::Map<Eigen::MatrixXd>(J, n_, n_) =
      colScale_.asDiagonal() * lu_.solve(rowScale_.asDiagonal() * -J0_);
  return 0;
}

bool ImplicitOde::linearization(double t, const double *y, Eigen::MatrixXd &J,
                                Eigen::VectorXcd &lambda) {
  std::vector<double> f(n_);
  J.resize(n_, n_);
  if (rhs(t, y, f.data()) != 0 || jacobian(t, y, f.data(), J.data()) != 0)
    return false;
  Eigen::EigenSolver<Eigen::MatrixXd> es(J, false);
  if (es.info() != Eigen::Success)
    return false;
  lambda = es.eigenvalues();
  return true;
}

} // namespace ldae::runtime
