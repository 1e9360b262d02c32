// Rank decisions (see Rank.h).
#include "numeric/Rank.h"

#include <cmath>
#include <limits>

namespace ldae::numeric {

int numericRank(const Eigen::MatrixXd &a, double threshold) {
  if (a.size() == 0)
    return 0;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (threshold > 0)
    lu.setThreshold(threshold);
  return static_cast<int>(lu.rank());
}

bool isNonsingular(const Eigen::MatrixXd &a, double threshold) {
  return a.rows() == a.cols() && numericRank(a, threshold) == a.rows();
}

SingularRange singularRange(const Eigen::MatrixXd &a) {
  if (a.size() == 0)
    return {};
  Eigen::VectorXd sv = a.jacobiSvd().singularValues();
  return {sv(0), sv(sv.size() - 1)};
}

SingularRange singularRangeByGram(const Eigen::MatrixXd &a) {
  if (a.size() == 0)
    return {};
  Eigen::MatrixXd gram = a.rows() <= a.cols()
                             ? Eigen::MatrixXd(a * a.transpose())
                             : Eigen::MatrixXd(a.transpose() * a);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(gram,
                                                    Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success)
    return singularRange(a);
  const Eigen::VectorXd &ev = es.eigenvalues(); // increasing
  // A wide matrix's Gram a a^T has the rows' count of eigenvalues, its
  // smallest the smallest of the a's min(rows, cols) singular values.
  return {std::sqrt(std::max(ev(ev.size() - 1), 0.0)),
          std::sqrt(std::max(ev(0), 0.0))};
}

double conditionNumber(const Eigen::MatrixXd &a) {
  const double inf = std::numeric_limits<double>::infinity();
  if (a.size() == 0)
    return 1;
  if (!a.allFinite())
    return inf;
  SingularRange s = singularRange(a);
  return s.min > 0 ? s.max / s.min : inf;
}

bool nearSingularLeftVector(const Eigen::MatrixXd &a, double relTol,
                            Eigen::VectorXd &u) {
  if (a.size() == 0)
    return false;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullU);
  const Eigen::VectorXd &sv = svd.singularValues();
  Eigen::Index last = sv.size() - 1;
  if (sv(last) > relTol * sv(0))
    return false;
  u = svd.matrixU().col(last);
  return true;
}

Eigen::VectorXd minimumNormSolution(const Eigen::MatrixXd &a,
                                    const Eigen::VectorXd &b,
                                    double threshold) {
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(a);
  if (threshold > 0)
    cod.setThreshold(threshold);
  return cod.solve(b);
}

} // namespace ldae::numeric
