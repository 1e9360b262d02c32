// Dynamic state selection of a block too large to enumerate (the dummy
// derivative method with Mattsson, Olsson and Soderlind's run-time choice):
// which candidate columns of the block's Jacobian become dummy derivatives
// at the current point. Shared by the dummy-derivatives pass (the choice at
// the start point) and the runtime (the choice during the run), so both
// pick the same columns for the same matrix.
//
// J is rows x (forced + candidates): the first `forced` columns are dummies
// already (chosen at a higher differentiation level); rows - forced of the
// candidates must join them. The choice eliminates the forced columns
// first (Householder QR) and takes the candidates a column-pivoted QR of
// what remains pivots first: the best conditioned choice greedily, with no
// enumeration of the binomially many subsets.
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace ldae::numeric {

/// The candidates' part of the rows the forced columns leave free (the
/// last rows - forced rows of Q^T J after a QR of the forced columns): a
/// (rows - forced) x candidates matrix on which the choice is made.
Eigen::MatrixXd reduceForced(const Eigen::MatrixXd &J, int forced);

/// The dummy candidates (indices into the columns of the reduced matrix
/// S, ascending) a column-pivoted QR of S picks; empty when S is not
/// finite or has fewer columns than rows.
std::vector<int> pivotDummies(const Eigen::MatrixXd &S);

/// The 2-norm condition of the square block of S's `dummies` columns,
/// scaled by S's largest singular value `smax` rather than the block's own
/// (a choice is measured against what the whole block could give):
/// smax / sigma_min(block); infinity when singular or not finite.
double dummyCondition(const Eigen::MatrixXd &S, const std::vector<int> &dummies,
                      double smax);

} // namespace ldae::numeric
