// The rank decision of a prolongation–projection step (seed 004, Le Vey):
// how many independent equations of order <= q a prolonged system implies.
// Its Jacobian J at a point of the system, with the columns of the jet
// coordinates of order <= q first ("low") and the higher ones after
// ("high"), has rank(J) - rank(J_high) independent combinations of rows in
// which every high coordinate cancels: the tangent space of the projection
// onto J_q has exactly that codimension. Knows nothing of the IR.
#pragma once

#include <Eigen/Dense>

namespace ldae::numeric {

/// Singular values at or below this fraction of the largest count as zero
/// (after the rows and columns are scaled to unit max-norm). The
/// prolongations of Andrews' squeezer at generic points (moving, not at
/// rest) have zeros at 2e-16 and nonzero values down to 2e-9: the cut
/// lies between, three orders above rounding in matrices of 500 columns.
inline constexpr double kProjectedRankTolerance = 1e-11;

struct ProjectedRank {
  int total = 0; ///< rank of J
  int high = 0;  ///< rank of its high-order columns
  /// The smallest ratio sigma_k / sigma_max counted as nonzero and the
  /// largest counted as zero, over both decisions: a gap of many orders of
  /// magnitude between them makes the decision trustworthy.
  double smallestKept = 1;
  double largestDropped = 0;
  /// Independent equations of order <= q: the codimension of the
  /// projection.
  int projected() const { return total - high; }
};

/// Ranks of `j` and of its columns from `lowCols` on, each by SVD after
/// scaling its rows and columns to unit max-norm (which leaves the ranks
/// unchanged but keeps equations of very different sizes comparable).
ProjectedRank projectedRank(const Eigen::MatrixXd &j, Eigen::Index lowCols,
                            double relTol = kProjectedRankTolerance);

} // namespace ldae::numeric
