// Wong sequences with SVD-based subspace operations (see WongSequence.h).
// Every subspace is carried as a matrix whose columns are an orthonormal
// basis, so dimensions compare directly and nested sequences stop when the
// dimension stops changing.
#include "numeric/WongSequence.h"

#include <algorithm>
#include <cassert>

namespace ldae::numeric {

using Eigen::Index;
using Eigen::MatrixXd;

static Index rankOf(const Eigen::VectorXd &sv, double tol) {
  Index r = 0;
  for (Index i = 0; i < sv.size(); ++i)
    if (sv(i) > tol)
      ++r;
  return r;
}

MatrixXd rangeBasis(const MatrixXd &a, double tol) {
  if (a.cols() == 0 || a.rows() == 0)
    return MatrixXd(a.rows(), 0);
  Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeThinU);
  return svd.matrixU().leftCols(rankOf(svd.singularValues(), tol));
}

MatrixXd nullBasis(const MatrixXd &a, double tol) {
  Index n = a.cols();
  if (a.rows() == 0 || n == 0) // Eigen's SVD of an empty matrix crashes
    return MatrixXd::Identity(n, n);
  Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeFullV);
  Index r = rankOf(svd.singularValues(), tol);
  return svd.matrixV().rightCols(n - r);
}

MatrixXd complementBasis(const MatrixXd &s, Index n, double tol) {
  if (s.cols() == 0)
    return MatrixXd::Identity(n, n);
  return nullBasis(s.transpose(), tol);
}

MatrixXd preimage(const MatrixXd &a, const MatrixXd &s, double tol) {
  // x maps into span(s) iff it is orthogonal, after a, to span(s)'s
  // complement. The complement of an orthonormal basis has singular values
  // 0 or 1, hence the fixed 0.5 there.
  MatrixXd q = complementBasis(rangeBasis(s, tol), a.rows(), 0.5);
  if (q.cols() == 0)
    return MatrixXd::Identity(a.cols(), a.cols());
  return nullBasis(q.transpose() * a, tol);
}

MatrixXd intersect(const MatrixXd &a, const MatrixXd &b, double tol) {
  assert(a.rows() == b.rows());
  if (a.cols() == 0 || b.cols() == 0)
    return MatrixXd(a.rows(), 0);
  MatrixXd oa = rangeBasis(a, tol), ob = rangeBasis(b, tol);
  MatrixXd ab(a.rows(), oa.cols() + ob.cols());
  ab << oa, -ob;
  MatrixXd k = nullBasis(ab, tol);
  return rangeBasis(oa * k.topRows(oa.cols()), tol);
}

bool sameSubspace(const MatrixXd &a, const MatrixXd &b, double tol) {
  MatrixXd oa = rangeBasis(a, tol), ob = rangeBasis(b, tol);
  if (oa.cols() != ob.cols())
    return false;
  MatrixXd ab(a.rows(), oa.cols() + ob.cols());
  ab << oa, ob;
  return rangeBasis(ab, tol).cols() == oa.cols();
}

static double absTol(const MatrixXd &E, const MatrixXd &F, double tol) {
  if (tol <= 0)
    tol = 1e-10;
  double scale = 0;
  if (E.size())
    scale = std::max(scale, E.jacobiSvd().singularValues()(0));
  if (F.size())
    scale = std::max(scale, F.jacobiSvd().singularValues()(0));
  return tol * std::max(scale, 1e-300);
}

MatrixXd jumpSpace(const MatrixXd &E, const MatrixXd &F, int *steps,
                   double tol) {
  assert(E.rows() == F.rows() && E.cols() == F.cols());
  double at = absTol(E, F, tol);
  Index n = E.cols();
  MatrixXd w(n, 0);
  for (int i = 0; i <= n + 1; ++i) {
    MatrixXd next = preimage(E, F * w, at);
    // W_i ⊆ W_{i+1}: equal dimension means equal subspace.
    if (next.cols() == w.cols()) {
      if (steps)
        *steps = i;
      return w;
    }
    w = std::move(next);
  }
  assert(false && "Wong sequence W did not become stationary");
  return w;
}

WongResult wongSequences(const MatrixXd &E, const MatrixXd &F, double tol) {
  double at = absTol(E, F, tol);
  Index n = E.cols();
  WongResult r;
  MatrixXd v = MatrixXd::Identity(n, n);
  for (int i = 0; i <= n + 1; ++i) {
    MatrixXd next = preimage(F, E * v, at);
    if (next.cols() == v.cols()) {
      r.stepsV = i;
      break;
    }
    v = std::move(next);
  }
  r.V = v;
  r.T = jumpSpace(E, F, &r.stepsT, tol);
  if (r.V.cols() + r.T.cols() == n) {
    MatrixXd vt(n, n);
    vt << r.V, r.T;
    r.regular = rangeBasis(vt, 1e-8).cols() == n;
  }
  return r;
}

MatrixXd leftPolynomialKernel(const MatrixXd &E, const MatrixXd &F,
                              int degree, double tol) {
  // Coefficient of s^j in sum_k s^k w_k^T (sE - F), transposed:
  // E^T w_{j-1} - F^T w_j = 0 for j = 0..degree+1.
  const Index m = E.rows(), n = E.cols(), d = degree;
  MatrixXd k = MatrixXd::Zero(n * (d + 2), m * (d + 1));
  for (Index j = 0; j <= d + 1; ++j) {
    if (j >= 1)
      k.block(j * n, (j - 1) * m, n, m) = E.transpose();
    if (j <= d)
      k.block(j * n, j * m, n, m) = -F.transpose();
  }
  return nullBasis(k, absTol(E, F, tol));
}

Eigen::VectorXd projectAlong(const WongResult &w, const Eigen::VectorXd &x) {
  assert(w.regular);
  Index n = x.size();
  MatrixXd vt(n, n);
  vt << w.V, w.T;
  Eigen::VectorXd c = vt.fullPivLu().solve(x);
  return w.V * c.head(w.V.cols());
}

} // namespace ldae::numeric
