// Ranks of a prolonged system's Jacobian and of its high-order part (see
// ProjectedRank.h).
#include "numeric/ProjectedRank.h"

#include <algorithm>
#include <vector>

namespace ldae::numeric {

namespace {

/// Divides every nonzero row and column by its largest magnitude: columns
/// first (jet coordinates of different orders have different scales), then
/// rows (a prolonged equation's coefficients grow with each derivative).
Eigen::MatrixXd equilibrated(const Eigen::MatrixXd &j) {
  Eigen::MatrixXd a = j;
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    double m = a.col(c).cwiseAbs().maxCoeff();
    if (m > 0)
      a.col(c) /= m;
  }
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    double m = a.row(r).cwiseAbs().maxCoeff();
    if (m > 0)
      a.row(r) /= m;
  }
  return a;
}

/// Rank of `a` by SVD, recording the decision's margins in `out`.
int svdRank(const Eigen::MatrixXd &a, double relTol, ProjectedRank &out) {
  if (a.size() == 0)
    return 0;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(a);
  const Eigen::VectorXd &sv = svd.singularValues();
  if (sv.size() == 0 || sv(0) == 0)
    return 0;
  int rank = 0;
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    double ratio = sv(k) / sv(0);
    if (ratio > relTol) {
      ++rank;
      out.smallestKept = std::min(out.smallestKept, ratio);
    } else {
      out.largestDropped = std::max(out.largestDropped, ratio);
    }
  }
  return rank;
}

} // namespace

ProjectedRank projectedRank(const Eigen::MatrixXd &j, Eigen::Index lowCols,
                            double relTol) {
  ProjectedRank out;
  if (j.size() == 0)
    return out;
  Eigen::MatrixXd a = equilibrated(j);
  out.total = svdRank(a, relTol, out);
  Eigen::Index highCols = a.cols() - lowCols;
  if (highCols > 0) {
    // Rows without a high coordinate cannot change the high rank.
    std::vector<Eigen::Index> rows;
    for (Eigen::Index r = 0; r < a.rows(); ++r)
      if (a.row(r).tail(highCols).cwiseAbs().maxCoeff() > 0)
        rows.push_back(r);
    Eigen::MatrixXd high(static_cast<Eigen::Index>(rows.size()), highCols);
    for (size_t i = 0; i < rows.size(); ++i)
      high.row(static_cast<Eigen::Index>(i)) = a.row(rows[i]).tail(highCols);
    out.high = svdRank(high, relTol, out);
  }
  return out;
}

} // namespace ldae::numeric
