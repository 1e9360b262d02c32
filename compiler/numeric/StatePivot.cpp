// Column-pivoted choice of dummy derivatives (see StatePivot.h). The
// choice and its measure work on the forced columns' Schur-like reduction,
// never on the whole block: the chain's velocity block is 3n x 4n, its
// reduction n x 2n, and SVDs of the whole were 80% of a 10-link run.
#include "numeric/StatePivot.h"
#include "numeric/Rank.h"

#include <algorithm>
#include <limits>

namespace ldae::numeric {

Eigen::MatrixXd reduceForced(const Eigen::MatrixXd &J, int forced) {
  const int cands = static_cast<int>(J.cols()) - forced;
  const int want = static_cast<int>(J.rows()) - forced;
  if (!J.allFinite())
    return Eigen::MatrixXd(); // no choice (pivotDummies: empty)
  if (forced == 0 || want <= 0)
    return J.rightCols(cands);
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(J.leftCols(forced));
  Eigen::MatrixXd rest = qr.householderQ().transpose() * J.rightCols(cands);
  return rest.bottomRows(want);
}

std::vector<int> pivotDummies(const Eigen::MatrixXd &S) {
  if (!S.allFinite() || S.rows() == 0 || S.cols() < S.rows())
    return {};
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> piv(S);
  std::vector<int> dummies;
  for (int k = 0; k < S.rows(); ++k)
    dummies.push_back(piv.colsPermutation().indices()[k]);
  std::sort(dummies.begin(), dummies.end());
  return dummies;
}

double dummyCondition(const Eigen::MatrixXd &S, const std::vector<int> &dummies,
                      double smax) {
  const double inf = std::numeric_limits<double>::infinity();
  if (static_cast<int>(dummies.size()) != S.rows() || !S.allFinite())
    return inf;
  Eigen::MatrixXd B(S.rows(), S.rows());
  for (size_t k = 0; k < dummies.size(); ++k)
    B.col(k) = S.col(dummies[k]);
  double smin = singularRangeByGram(B).min;
  return smin > 0 && smax > 0 ? smax / smin : inf;
}

} // namespace ldae::numeric
