// Ranks of a prolonged system's Jacobian and of its high-order part (see
// ProjectedRank.h).
#include "numeric/ProjectedRank.h"

#include <algorithm>
#include <vector>

namespace ldae::numeric {

namespace {

/// Divides every nonzero column by its largest magnitude (jet coordinates
/// of different orders have different scales).
Eigen::MatrixXd columnsScaled(const Eigen::MatrixXd &j) {
  Eigen::MatrixXd a = j;
  for (Eigen::Index c = 0; c < a.cols(); ++c) {
    double m = a.col(c).cwiseAbs().maxCoeff();
    if (m > 0)
      a.col(c) /= m;
  }
  return a;
}

/// Divides every nonzero column, then row, by its largest magnitude (a
/// prolonged equation's coefficients grow with each derivative).
Eigen::MatrixXd equilibrated(const Eigen::MatrixXd &j) {
  Eigen::MatrixXd a = columnsScaled(j);
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    double m = a.row(r).cwiseAbs().maxCoeff();
    if (m > 0)
      a.row(r) /= m;
  }
  return a;
}

/// The number of singular values `sv` (largest first) above relTol times
/// the largest, recording the decision's margins in `out`.
int countRank(const Eigen::VectorXd &sv, double relTol, ProjectedRank &out) {
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

/// Rank of `a` by SVD, recording the decision's margins in `out`.
int svdRank(const Eigen::MatrixXd &a, double relTol, ProjectedRank &out) {
  if (a.size() == 0)
    return 0;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(a);
  return countRank(svd.singularValues(), relTol, out);
}

} // namespace

ProjectedRank projectedRank(const Eigen::MatrixXd &j, Eigen::Index lowCols,
                            double relTol) {
  ProjectedRank out;
  if (j.size() == 0)
    return out;
  const Eigen::Index highCols = j.cols() - lowCols;
  if (highCols <= 0 || lowCols <= 0) {
    out.total = svdRank(equilibrated(j), relTol, out);
    if (highCols > 0)
      out.high = out.total; // every column is high: nothing projects
    return out;
  }
  // rank J - rank J_high is the rank of N^T J_low, N a basis of the
  // combinations of rows that cancel every high coordinate: decided so,
  // it is not the difference of two large ranks. Andrews' squeezer
  // prolonged four times: the 385 x 462 Jacobian's smallest singular
  // values run down to 4e-13 without a gap, while J_high has one (4e-8,
  // then 2e-16) and N^T J_low (152 x 154) keeps its 152 above 1e-11.
  // Each row is scaled by its largest high entry (by its largest entry
  // when it has none): scaled with the whole row, a row whose largest
  // entry is a low coordinate's left its high part tiny.
  Eigen::MatrixXd a = columnsScaled(j);
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    double m = a.row(r).tail(highCols).cwiseAbs().maxCoeff();
    if (m == 0)
      m = a.row(r).cwiseAbs().maxCoeff();
    if (m > 0)
      a.row(r) /= m;
  }
  Eigen::BDCSVD<Eigen::MatrixXd> svd(a.rightCols(highCols),
                                     Eigen::ComputeFullU);
  out.high = countRank(svd.singularValues(), relTol, out);
  const Eigen::MatrixXd cancelling =
      svd.matrixU().rightCols(a.rows() - out.high);
  const Eigen::MatrixXd projected =
      cancelling.transpose() * a.leftCols(lowCols);
  out.total = out.high + svdRank(equilibrated(projected), relTol, out);
  return out;
}

} // namespace ldae::numeric
