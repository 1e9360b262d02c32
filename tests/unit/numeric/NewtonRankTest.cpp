// Newton / Gauss–Newton, rank decisions and the KLU wrapper on systems
// whose solution, rank or condition is known by hand.
#include "numeric/Newton.h"
#include "numeric/Rank.h"
#include "numeric/SparseLu.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ldae::numeric;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
/// x^2 + y^2 = 4, x - y = 0: the root (sqrt 2, sqrt 2) from (1, 0.5).
bool circleLine(const VectorXd &x, VectorXd &r) {
  r.resize(2);
  r << x[0] * x[0] + x[1] * x[1] - 4, x[0] - x[1];
  return true;
}
} // namespace

TEST(Newton, SquareSystemWithFiniteDifferences) {
  VectorXd x(2);
  x << 1, 0.5;
  NewtonResult res = gaussNewton(circleLine, {}, x);
  ASSERT_TRUE(res.converged());
  EXPECT_NEAR(x[0], std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(x[1], std::sqrt(2.0), 1e-9);
  EXPECT_LT(res.iterations, 10);
}

TEST(Newton, AnalyticJacobianGivesTheSameRoot) {
  VectorXd x(2);
  x << 1, 0.5;
  JacobianFn jac = [](const VectorXd &x, MatrixXd &J) {
    J.resize(2, 2);
    J << 2 * x[0], 2 * x[1], 1, -1;
    return true;
  };
  ASSERT_TRUE(gaussNewton(circleLine, jac, x).converged());
  EXPECT_NEAR(x[0], std::sqrt(2.0), 1e-12);
}

TEST(Newton, UnderdeterminedTakesTheMinimumNormStep) {
  // x + y = 2 from (0, 0): the nearest point is (1, 1).
  ResidualFn f = [](const VectorXd &x, VectorXd &r) {
    r.resize(1);
    r << x[0] + x[1] - 2;
    return true;
  };
  VectorXd x = VectorXd::Zero(2);
  ASSERT_TRUE(gaussNewton(f, {}, x).converged());
  EXPECT_NEAR(x[0], 1, 1e-9);
  EXPECT_NEAR(x[1], 1, 1e-9);
}

TEST(Newton, InconsistentAndDomainErrors) {
  // x = 1 and x = 2: the least-squares point is not a root.
  ResidualFn conflict = [](const VectorXd &x, VectorXd &r) {
    r.resize(2);
    r << x[0] - 1, x[0] - 2;
    return true;
  };
  VectorXd x = VectorXd::Zero(1);
  NewtonResult res = gaussNewton(conflict, {}, x);
  EXPECT_EQ(res.status, NewtonStatus::NotConverged);
  EXPECT_NEAR(x[0], 1.5, 1e-9);
  EXPECT_NEAR(res.residualNorm, 0.5, 1e-9);
  // sqrt(x) = 1 from x = -1: not evaluable.
  ResidualFn domain = [](const VectorXd &x, VectorXd &r) {
    r.resize(1);
    r << std::sqrt(x[0]) - 1;
    return true;
  };
  x << -1;
  EXPECT_EQ(gaussNewton(domain, {}, x).status, NewtonStatus::EvaluationFailed);
}

TEST(Newton, FiniteDifferenceJacobianOfAKnownFunction) {
  VectorXd x(2), r0;
  x << 3, -2;
  circleLine(x, r0);
  MatrixXd J;
  ASSERT_TRUE(finiteDifferenceJacobian(circleLine, x, r0, J));
  EXPECT_NEAR(J(0, 0), 6, 1e-6);
  EXPECT_NEAR(J(0, 1), -4, 1e-6);
  EXPECT_NEAR(J(1, 0), 1, 1e-7);
  EXPECT_NEAR(J(1, 1), -1, 1e-7);
}

TEST(Rank, KnownRanks) {
  MatrixXd a(3, 3);
  a << 1, 2, 3, 4, 5, 6, 7, 8, 9; // rank 2
  EXPECT_EQ(numericRank(a), 2);
  EXPECT_FALSE(isNonsingular(a));
  EXPECT_TRUE(isNonsingular(MatrixXd::Identity(4, 4)));
  EXPECT_EQ(numericRank(MatrixXd::Zero(2, 5)), 0);
  EXPECT_EQ(numericRank(MatrixXd(0, 0)), 0);
  // A pivot 1e-12 below the largest: rank 2 at the index-1 threshold
  // (1e-10), rank 3 at Eigen's default.
  MatrixXd d = MatrixXd::Identity(3, 3);
  d(2, 2) = 1e-12;
  EXPECT_EQ(numericRank(d, kNonsingularThreshold), 2);
  EXPECT_EQ(numericRank(d), 3);
  // 3 x 2 with independent columns.
  MatrixXd tall(3, 2);
  tall << 1, 0, 0, 1, 1, 1;
  EXPECT_EQ(numericRank(tall, 1e-9), 2);
}

TEST(Rank, ConditionNumber) {
  MatrixXd a = MatrixXd::Zero(2, 2);
  a(0, 0) = 4;
  a(1, 1) = 0.5;
  EXPECT_DOUBLE_EQ(conditionNumber(a), 8);
  SingularRange s = singularRange(a);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_DOUBLE_EQ(s.min, 0.5);
  a(1, 1) = 0;
  EXPECT_TRUE(std::isinf(conditionNumber(a)));
  a(0, 1) = NAN;
  EXPECT_TRUE(std::isinf(conditionNumber(a)));
}

// The Gram route against the SVD on a wide, a tall and a square matrix
// with known singular values (U diag(s) V^T, U and V orthogonal), the
// square one at a condition of 1e6: sigma_min to eps * 1e12 relative.
TEST(Rank, SingularRangeByGramMatchesTheSvd) {
  auto withValues = [](int rows, int cols, const Eigen::VectorXd &s) {
    MatrixXd u = MatrixXd::Random(rows, rows).householderQr().householderQ();
    MatrixXd v = MatrixXd::Random(cols, cols).householderQr().householderQ();
    MatrixXd d = MatrixXd::Zero(rows, cols);
    for (int i = 0; i < s.size(); ++i)
      d(i, i) = s(i);
    return MatrixXd(u * d * v.transpose());
  };
  Eigen::VectorXd s6(6), s20(20);
  s6 << 40, 9, 3, 1, 0.5, 0.25;
  for (int i = 0; i < 20; ++i)
    s20(i) = std::pow(10.0, -6.0 * i / 19); // 1 down to 1e-6
  struct Case {
    MatrixXd a;
    double max, min, tol;
  };
  for (const Case &c : {Case{withValues(6, 7, s6), 40, 0.25, 1e-12},
                        Case{withValues(7, 6, s6), 40, 0.25, 1e-12},
                        Case{withValues(20, 20, s20), 1, 1e-6, 1e-3}}) {
    SingularRange g = singularRangeByGram(c.a);
    EXPECT_NEAR(g.max, c.max, 1e-12 * c.max);
    EXPECT_NEAR(g.min, c.min, c.tol * c.min);
  }
  EXPECT_EQ(singularRangeByGram(MatrixXd()).max, 0);
}

TEST(SparseLu, SolvesAKnownSystem) {
  // [[4, 1, 0], [1, 3, 0], [0, 0, 2]] x = [6, 7, 4]: x = (1, 2, 2).
  CscMatrix a;
  a.n = 3;
  a.colptr = {0, 2, 4, 5};
  a.rowind = {0, 1, 0, 1, 2};
  a.values = {4, 1, 1, 3, 2};
  SparseLu lu;
  ASSERT_TRUE(lu.factor(a));
  double b[3] = {6, 7, 4};
  ASSERT_TRUE(lu.solve(b));
  EXPECT_NEAR(b[0], 1, 1e-14);
  EXPECT_NEAR(b[1], 2, 1e-14);
  EXPECT_NEAR(b[2], 2, 1e-14);
  // The transposed solve of a symmetric matrix is the same.
  double c[3] = {6, 7, 4};
  ASSERT_TRUE(lu.solve(c, true));
  EXPECT_NEAR(c[1], 2, 1e-14);
  EXPECT_GT(lu.rcondEstimate(), 0.1);
  double y[3];
  a.multiply(b, y);
  EXPECT_NEAR(y[0], 6, 1e-14);
  EXPECT_EQ(a.transposed().rowind, (std::vector<int>{0, 1, 0, 1, 2}));
}

TEST(SparseLu, NamesTheSingularColumn) {
  // Column 1 is structurally empty.
  CscMatrix a;
  a.n = 2;
  a.colptr = {0, 2, 2};
  a.rowind = {0, 1};
  a.values = {1, 1};
  SparseLu lu;
  EXPECT_FALSE(lu.factor(a));
  EXPECT_EQ(lu.singularColumn(), 1);
}

TEST(Rank, NearSingularLeftVectorNamesTheDependentRows) {
  // Rows 0 and 2 are equal: u ~ (1, 0, -1) / sqrt(2).
  MatrixXd a(3, 3);
  a << 1, 2, 3, 0, 1, 4, 1, 2, 3;
  VectorXd u;
  ASSERT_TRUE(nearSingularLeftVector(a, 1e-10, u));
  EXPECT_NEAR(std::fabs(u[0]), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(u[1], 0, 1e-12);
  EXPECT_NEAR(u[0] + u[2], 0, 1e-12);
  EXPECT_FALSE(nearSingularLeftVector(MatrixXd::Identity(3, 3), 1e-10, u));
}

TEST(Rank, MinimumNormSolution) {
  // x + y = 2 (one row): (1, 1); a rank-deficient square system the same.
  MatrixXd a(1, 2);
  a << 1, 1;
  VectorXd b(1);
  b << 2;
  VectorXd x = minimumNormSolution(a, b);
  EXPECT_NEAR(x[0], 1, 1e-14);
  EXPECT_NEAR(x[1], 1, 1e-14);
  MatrixXd s(2, 2);
  s << 1, 1, 2, 2;
  VectorXd c(2);
  c << 2, 4;
  x = minimumNormSolution(s, c, 1e-12);
  EXPECT_NEAR(x[0], 1, 1e-12);
  EXPECT_NEAR(x[1], 1, 1e-12);
}
