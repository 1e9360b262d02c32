// Wong sequences: jump and consistent subspaces of small pencils whose
// Kronecker structure is known by hand.
#include "numeric/WongSequence.h"

#include <gtest/gtest.h>

using namespace ldae::numeric;
using Eigen::MatrixXd;
using Eigen::VectorXd;

TEST(WongSequence, OdeHasNoJumps) {
  MatrixXd E = MatrixXd::Identity(3, 3), F = MatrixXd::Random(3, 3);
  WongResult w = wongSequences(E, F);
  EXPECT_EQ(w.T.cols(), 0);
  EXPECT_EQ(w.V.cols(), 3);
  EXPECT_EQ(w.stepsT, 0);
  EXPECT_TRUE(w.regular);
}

TEST(WongSequence, IndexOneJumpSpaceIsKernelOfE) {
  // x' = -x + z, 0 = z - 2x: T = ker E = span(e_z), V = span((1, 2)).
  MatrixXd E(2, 2), F(2, 2);
  E << 1, 0, 0, 0;
  F << -1, 1, 2, -1;
  WongResult w = wongSequences(E, F);
  ASSERT_EQ(w.T.cols(), 1);
  EXPECT_NEAR(std::abs(w.T(1, 0)), 1.0, 1e-14);
  EXPECT_NEAR(w.T(0, 0), 0.0, 1e-14);
  ASSERT_EQ(w.V.cols(), 1);
  EXPECT_NEAR(w.V(1, 0) / w.V(0, 0), 2.0, 1e-12);
  EXPECT_EQ(w.stepsT, 1);
  EXPECT_TRUE(w.regular);
  // Projection along T keeps x: (1, 5) -> (1, 2).
  VectorXd p = projectAlong(w, Eigen::Vector2d(1, 5));
  EXPECT_NEAR(p(0), 1.0, 1e-12);
  EXPECT_NEAR(p(1), 2.0, 1e-12);
}

TEST(WongSequence, IndexTwoLinear) {
  // x1' = x2, x3' = x2 - x3, 0 = x1 (E x' = F x).
  // By hand: W1 = span(e2), W2 = span(e2, e1 + e3) = W3, so T has
  // dimension 2 and index 2; V = span(e3).
  MatrixXd E(3, 3), F(3, 3);
  E << 1, 0, 0, 0, 0, 1, 0, 0, 0;
  F << 0, 1, 0, 0, 1, -1, -1, 0, 0;
  WongResult w = wongSequences(E, F);
  EXPECT_EQ(w.stepsT, 2);
  EXPECT_TRUE(w.regular);
  MatrixXd T(3, 2);
  T << 0, 1, 1, 0, 0, 1;
  EXPECT_TRUE(sameSubspace(w.T, T, 1e-10));
  ASSERT_EQ(w.V.cols(), 1);
  EXPECT_NEAR(std::abs(w.V(2, 0)), 1.0, 1e-12);
  // (a, b, c) moves to (0, 0, c - a) along T.
  VectorXd p = projectAlong(w, Eigen::Vector3d(2, 3, 1));
  EXPECT_NEAR(p(0), 0.0, 1e-12);
  EXPECT_NEAR(p(1), 0.0, 1e-12);
  EXPECT_NEAR(p(2), -1.0, 1e-12);
}

TEST(WongSequence, SingularPencilIsNotRegular) {
  // 0 = 0 row and a free variable: det(sE - F) == 0.
  MatrixXd E(2, 2), F(2, 2);
  E << 1, 0, 0, 0;
  F << 0, 0, 0, 0;
  WongResult w = wongSequences(E, F);
  EXPECT_FALSE(w.regular);
}

TEST(WongSequence, SubspaceOperations) {
  MatrixXd a(3, 2), b(3, 2);
  a << 1, 0, 0, 1, 0, 0; // xy-plane
  b << 1, 0, 0, 0, 0, 1; // xz-plane
  MatrixXd i = intersect(a, b, 1e-12);
  ASSERT_EQ(i.cols(), 1);
  EXPECT_NEAR(std::abs(i(0, 0)), 1.0, 1e-14);
  EXPECT_EQ(nullBasis(a.transpose(), 1e-12).cols(), 1);
  // Preimage of the x-axis under a projection onto the xy-plane.
  MatrixXd P = MatrixXd::Zero(3, 3);
  P(0, 0) = P(1, 1) = 1;
  MatrixXd pre = preimage(P, Eigen::Vector3d(1, 0, 0), 1e-12);
  MatrixXd expect(3, 2);
  expect << 1, 0, 0, 0, 0, 1;
  EXPECT_TRUE(sameSubspace(pre, expect, 1e-12));
}
