// Numeric rank decisions shared by the passes and the runtime, each with
// its threshold stated once here rather than at every call site.
//
//  - numericRank: rank-revealing LU with full pivoting. A pivot counts as
//    nonzero when |pivot| > threshold * |largest pivot|; threshold 0 means
//    Eigen's default, machine epsilon times the matrix's larger dimension.
//    An order of magnitude cheaper than an SVD, and exact enough for the
//    yes/no questions asked of it (is this block nonsingular, does this
//    row add to the rank).
//  - conditionNumber: the 2-norm condition sigma_max / sigma_min by SVD
//    (infinite for a singular or non-finite matrix), for the quantitative
//    questions (how close to singular is a state set's pivot).
#pragma once

#include <Eigen/Dense>

namespace ldae::numeric {

/// Threshold of the index-1 and structural-nonsingularity tests.
inline constexpr double kNonsingularThreshold = 1e-10;

/// Rank of `a` by full-pivot LU (see the file comment for `threshold`).
int numericRank(const Eigen::MatrixXd &a, double threshold = 0);

/// Whether the square matrix `a` has full rank under `threshold`.
bool isNonsingular(const Eigen::MatrixXd &a, double threshold = 0);

/// The largest and smallest singular values of `a` (both 0 when empty).
struct SingularRange {
  double max = 0, min = 0;
};
SingularRange singularRange(const Eigen::MatrixXd &a);

/// The same from the eigenvalues of the smaller Gram matrix (a a^T or
/// a^T a): 7x cheaper than the SVD at 20 x 21 (14 against 97 us), for the
/// run-time state selection's every-step conditions. Squaring costs
/// sigma_min relative accuracy eps * (sigma_max / sigma_min)^2 (1e-4 at a
/// condition of 1e6, the order of 1 beyond 1e8, where the matrix counts as
/// singular anyway): enough for the switching thresholds (a condition of 4
/// and a factor of 2), not for rank decisions.
SingularRange singularRangeByGram(const Eigen::MatrixXd &a);

/// sigma_max / sigma_min of `a` (infinity when singular or not finite).
double conditionNumber(const Eigen::MatrixXd &a);

/// For a square `a`: when sigma_min(a) <= relTol * sigma_max(a), true, with
/// `u` the left singular vector of sigma_min (the combination of rows that (nearly)
/// vanishes: which equations a singular matrix singles out).
bool nearSingularLeftVector(const Eigen::MatrixXd &a, double relTol,
                            Eigen::VectorXd &u);

/// The minimum-norm least-squares solution of a x = b by a complete
/// orthogonal decomposition; `threshold` as in numericRank (relative to
/// the largest pivot; 0: Eigen's default).
Eigen::VectorXd minimumNormSolution(const Eigen::MatrixXd &a,
                                    const Eigen::VectorXd &b,
                                    double threshold = 0);

} // namespace ldae::numeric
