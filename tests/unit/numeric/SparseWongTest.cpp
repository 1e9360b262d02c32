// Wong sequences of sparse pencils by reduction (SparseWong.h): each pencil
// is analyzed both by the reduction (denseLimit 0) and by the dense Wong
// sequences, which must agree, and against the Kronecker structure known
// by hand.
#include "numeric/SparseWong.h"
#include "numeric/WongSequence.h"

#include <gtest/gtest.h>

using namespace ldae::numeric;
using Eigen::MatrixXd;

namespace {

struct Builder {
  SparsePencil p;
  explicit Builder(int n) {
    p.rows = p.cols = n;
  }
  void e(int r, int c, double v) { p.E.push_back({r, c, v}); }
  void f(int r, int c, double v) { p.F.push_back({r, c, v}); }
};

PencilAnalysis both(const SparsePencil &p, const char *path = nullptr) {
  PencilAnalysis dense = analyzePencil(p, {.denseLimit = 100000});
  PencilAnalysis red = analyzePencil(p, {.denseLimit = 0});
  EXPECT_EQ(dense.path, "dense");
  if (path) {
    EXPECT_EQ(red.path, path);
  }
  EXPECT_TRUE(red.computed);
  EXPECT_EQ(red.dimV, dense.dimV);
  EXPECT_EQ(red.dimW, dense.dimW);
  EXPECT_EQ(red.stepsW, dense.stepsW);
  EXPECT_EQ(red.regular, dense.regular);
  EXPECT_EQ(red.freeDirections.cols(), dense.freeDirections.cols());
  if (red.freeDirections.cols() == dense.freeDirections.cols()) {
    EXPECT_TRUE(sameSubspace(red.freeDirections, dense.freeDirections, 1e-8));
  }
  return red;
}

/// An RC ladder of `n` sections with the resistor currents as unknowns:
/// C v_k' = i_k - i_{k+1}, 0 = R i_k - (v_{k-1} - v_k) (v_0 = 0), the last
/// section open: index 1, dim V = n.
SparsePencil rcLadder(int n) {
  Builder b(2 * n);
  for (int k = 0; k < n; ++k) {
    int v = k, i = n + k;
    b.e(k, v, 1e-6 * (1 + k % 3));
    b.f(k, i, 1);
    if (k + 1 < n)
      b.f(k, i + 1, -1);
    b.f(n + k, i, -100.0);
    b.f(n + k, v, -1);
    if (k > 0)
      b.f(n + k, v - 1, 1);
  }
  return b.p;
}

} // namespace

TEST(SparseWong, RcLadderIsIndexOne) {
  PencilAnalysis a = both(rcLadder(30), "structured");
  EXPECT_EQ(a.dimV, 30);
  EXPECT_EQ(a.dimW, 30);
  EXPECT_EQ(a.stepsW, 1);
  EXPECT_EQ(a.indexOnePairs, 30);
  EXPECT_TRUE(a.regular);
}

TEST(SparseWong, CapacitorLoopIsIndexTwo) {
  // Two capacitors in parallel fed through a resistor: v1 = v2 is a
  // constraint on two differential unknowns, the capacitor currents are
  // the multipliers. Unknowns v1 v2 i1 i2 ir:
  //   C1 v1' = i1, C2 v2' = i2, 0 = v1 - v2, 0 = i1 + i2 + ir,
  //   0 = R ir + v1.
  // One dynamic degree of freedom; index 2.
  Builder b(5);
  b.e(0, 0, 1e-3);
  b.f(0, 2, 1);
  b.e(1, 1, 2e-3);
  b.f(1, 3, 1);
  b.f(2, 0, 1);
  b.f(2, 1, -1);
  b.f(3, 2, 1);
  b.f(3, 3, 1);
  b.f(3, 4, 1);
  b.f(4, 4, 10);
  b.f(4, 0, 1);
  PencilAnalysis a = both(b.p, "structured");
  EXPECT_EQ(a.dimV, 1);
  EXPECT_EQ(a.dimW, 4);
  EXPECT_EQ(a.stepsW, 2);
  EXPECT_TRUE(a.regular);
}

TEST(SparseWong, IndexThreeChain) {
  // q' = v, v' = -q + l, 0 = q: the linear pendulum's index-3 structure.
  Builder b(3);
  b.e(0, 0, 1);
  b.f(0, 1, 1);
  b.e(1, 1, 1);
  b.f(1, 0, -1);
  b.f(1, 2, 1);
  b.f(2, 0, 1);
  PencilAnalysis a = both(b.p, "structured");
  EXPECT_EQ(a.dimV, 0);
  EXPECT_EQ(a.dimW, 3);
  EXPECT_EQ(a.stepsW, 3);
  EXPECT_TRUE(a.regular);
}

TEST(SparseWong, CancellationClearedByAColumnOperation) {
  // x' + y' = u, x' + y' = x + y: det(sE - F) = 0; x - y is free.
  Builder b(2);
  b.e(0, 0, 1);
  b.e(0, 1, 1);
  b.e(1, 0, 1);
  b.e(1, 1, 1);
  b.f(1, 0, 1);
  b.f(1, 1, 1);
  PencilAnalysis a = both(b.p, "structured");
  EXPECT_FALSE(a.regular);
  ASSERT_EQ(a.freeDirections.cols(), 1);
  EXPECT_NEAR(a.freeDirections(0, 0) / a.freeDirections(1, 0), -1, 1e-12);
}

TEST(SparseWong, UnknownNothingReadsIsFree) {
  // x' = -x + z, 0 = z - x, and w read by no equation (3 rows: one 0 = 0).
  Builder b(3);
  b.e(0, 0, 1);
  b.f(0, 0, -1);
  b.f(0, 1, 1);
  b.f(1, 1, 1);
  b.f(1, 0, -1);
  PencilAnalysis a = both(b.p);
  EXPECT_FALSE(a.regular);
  ASSERT_EQ(a.freeDirections.cols(), 1);
  EXPECT_NEAR(std::abs(a.freeDirections(2, 0)), 1, 1e-12);
}

TEST(SparseWong, LeftKernelFindsTheInputCondition) {
  // x' + y' = f1, 0 = -(x + y) + f2: w(s) = (1, -s) up to scale, so
  // f1 - f2' must vanish.
  MatrixXd E(2, 2), F(2, 2);
  E << 1, 1, 0, 0;
  F << 0, 0, -1, -1;
  EXPECT_EQ(leftPolynomialKernel(E, F, 0).cols(), 0);
  MatrixXd w = leftPolynomialKernel(E, F, 1);
  ASSERT_EQ(w.cols(), 1);
  Eigen::Vector4d v = w.col(0) / w(0, 0); // w0 = (1, 0), w1 = (0, -1)
  EXPECT_NEAR(v(1), 0, 1e-12);
  EXPECT_NEAR(v(2), 0, 1e-12);
  EXPECT_NEAR(v(3), -1, 1e-12);
}

namespace {

/// A random connected RLC network with voltage sources in nodal form:
/// unknowns the node potentials (ground excluded) and every branch
/// current; rows Kirchhoff's current law per node and one constitutive
/// law per branch (C (e_a - e_b)' = i, L i' = e_a - e_b, R i = e_a - e_b,
/// e_a - e_b = u). Loops of capacitors and sources and cutsets of
/// inductors appear at random: index 1 or 2.
SparsePencil randomCircuit(unsigned seed, int nodes, int branches) {
  std::srand(seed);
  auto uniform = [] { return 0.5 + double(std::rand()) / RAND_MAX; };
  std::vector<std::pair<int, int>> ends;
  for (int k = 0; k < branches; ++k) {
    // The first `nodes` branches make a spanning tree (node k+1 to an
    // earlier one or ground); the rest connect random pairs.
    int a = k < nodes ? k + 1 : 1 + std::rand() % nodes;
    int b = k < nodes ? std::rand() % (k + 1) : std::rand() % (nodes + 1);
    if (a == b)
      b = 0;
    ends.push_back({a, b});
  }
  Builder bld(nodes + branches);
  for (int k = 0; k < branches; ++k) {
    auto [a, b] = ends[k];
    int i = nodes + k, row = nodes + k;
    if (a > 0)
      bld.f(a - 1, i, 1); // KCL: the branch current leaves a
    if (b > 0)
      bld.f(b - 1, i, -1);
    int kind = k == 0 ? 3 : std::rand() % 3; // one source, then R, C, L
    double value = uniform() * (kind == 1 ? 1e-6 : kind == 2 ? 1e-2 : 1e2);
    auto potentialDifference = [&](bool derivative, double s) {
      if (a > 0)
        derivative ? bld.e(row, a - 1, s) : bld.f(row, a - 1, s);
      if (b > 0)
        derivative ? bld.e(row, b - 1, -s) : bld.f(row, b - 1, -s);
    };
    switch (kind) {
    case 0: // R i = e_a - e_b
      bld.f(row, i, -value);
      potentialDifference(false, 1);
      break;
    case 1: // C (e_a - e_b)' = i
      potentialDifference(true, value);
      bld.f(row, i, 1);
      break;
    case 2: // L i' = e_a - e_b
      bld.e(row, i, value);
      potentialDifference(false, 1);
      break;
    default: // e_a - e_b = u(t)
      potentialDifference(false, -1);
      break;
    }
  }
  return bld.p;
}

} // namespace

TEST(SparseWong, RandomCircuitsAgreeWithDense) {
  int structured = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    PencilAnalysis a = both(randomCircuit(seed, 8, 16));
    structured += a.path == "structured";
  }
  EXPECT_GT(structured, 20); // the reduction, not the fallback, did most
  for (unsigned seed = 41; seed <= 50; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    both(randomCircuit(seed, 30, 60));
  }
}
