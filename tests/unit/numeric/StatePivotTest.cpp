// The run-time choice of dummy derivatives (numeric/StatePivot.h) on the
// link constraints of pendulum chains, whose good and singular choices are
// known by hand.
#include "numeric/StatePivot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace ldae::numeric;
using Eigen::MatrixXd;

namespace {

/// The Jacobian of the chain's link constraints |p_i - p_{i-1}|^2 = 1 over
/// (x1..xn, y1..yn) at link directions (dx_i, dy_i).
MatrixXd chainJacobian(const std::vector<std::pair<double, double>> &d) {
  const int n = static_cast<int>(d.size());
  MatrixXd J = MatrixXd::Zero(n, 2 * n);
  for (int i = 0; i < n; ++i) {
    J(i, i) = 2 * d[i].first;
    J(i, n + i) = 2 * d[i].second;
    if (i > 0) {
      J(i, i - 1) = -2 * d[i].first;
      J(i, n + i - 1) = -2 * d[i].second;
    }
  }
  return J;
}

} // namespace

TEST(StatePivot, PendulumTakesTheLargerCoordinate) {
  // Hanging nearly straight down: y is the dummy, x the state.
  EXPECT_EQ(pivotDummies(chainJacobian({{0.1, -0.995}})), std::vector<int>{1});
  EXPECT_EQ(pivotDummies(chainJacobian({{0.995, 0.1}})), std::vector<int>{0});
}

TEST(StatePivot, StraightChainAvoidsTheSingularChoices) {
  // All three links along (0.6, -0.8): choosing x1 and y1 together (rows 1
  // and 2 parallel on them) is singular; the pivoted choice is the y's.
  MatrixXd J = chainJacobian({{0.6, -0.8}, {0.6, -0.8}, {0.6, -0.8}});
  std::vector<int> d = pivotDummies(J);
  EXPECT_EQ(d, (std::vector<int>{3, 4, 5}));
  const double smax = 4; // any common scale
  EXPECT_TRUE(std::isfinite(dummyCondition(J, d, smax)));
  EXPECT_GT(dummyCondition(J, {0, 3, 4}, smax), 1e12);
  // The y's (entries 1.6) are better conditioned than the x's (1.2).
  EXPECT_LT(dummyCondition(J, d, smax), dummyCondition(J, {0, 1, 2}, smax));
}

TEST(StatePivot, ForcedColumnsAreEliminatedFirst) {
  // Rows: a + b = 0 (a forced), b - 0.1 c + 2 d = 0: with a taking the
  // first row, the second row's largest candidate after elimination is d.
  MatrixXd J(2, 4);
  J << 1, 1, 0, 0, //
      0, 1, -0.1, 2;
  MatrixXd S = reduceForced(J, 1);
  ASSERT_EQ(S.rows(), 1);
  EXPECT_NEAR(std::fabs(S(0, 0)), 1, 1e-15);
  EXPECT_EQ(pivotDummies(S), std::vector<int>{2});
  // Not finite: no choice.
  J(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(pivotDummies(reduceForced(J, 1)).empty());
}
