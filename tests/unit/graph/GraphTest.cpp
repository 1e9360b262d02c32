// Unit tests of the IR-free graph algorithms: matching, SCC/BLT,
// Dulmage–Mendelsohn and Pantelides on small structures with known answers.
#include "graph/DulmageMendelsohn.h"
#include "graph/Matching.h"
#include "graph/Pantelides.h"
#include "graph/Scc.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>

using namespace ldae::graph;

namespace {
BipartiteGraph makeGraph(int cols, std::vector<std::vector<int>> rows) {
  BipartiteGraph g;
  g.numCols = cols;
  g.rows = std::move(rows);
  return g;
}

bool isValidMatching(const BipartiteGraph &g, const Matching &m) {
  int size = 0;
  for (int r = 0; r < g.numRows(); ++r) {
    int c = m.rowMate[r];
    if (c < 0)
      continue;
    ++size;
    if (m.colMate[c] != r)
      return false;
    if (std::find(g.rows[r].begin(), g.rows[r].end(), c) == g.rows[r].end())
      return false;
  }
  return size == m.size;
}
} // namespace

TEST(Matching, FindsPerfectMatchingNeedingAugmentation) {
  // Greedy takes r0-c0 first; r1 only has c0, so an augmenting path is needed.
  BipartiteGraph g = makeGraph(3, {{0, 1}, {0}, {1, 2}});
  Matching m = maximumMatching(g);
  EXPECT_EQ(m.size, 3);
  EXPECT_EQ(m.rowMate[1], 0);
  EXPECT_EQ(m.rowMate[0], 1);
  EXPECT_EQ(m.rowMate[2], 2);
  EXPECT_TRUE(isValidMatching(g, m));
}

TEST(Matching, MaximumOfDeficientGraph) {
  // Rows 0 and 1 both contain only column 0.
  BipartiteGraph g = makeGraph(2, {{0}, {0}, {0, 1}});
  Matching m = maximumMatching(g);
  EXPECT_EQ(m.size, 2);
  EXPECT_TRUE(isValidMatching(g, m));
}

TEST(Matching, RespectsColumnMask) {
  BipartiteGraph g = makeGraph(2, {{0, 1}, {1}});
  Matching m = maximumMatching(g, {1, 0});
  EXPECT_EQ(m.size, 1);
  EXPECT_EQ(m.rowMate[0], 0);
  EXPECT_EQ(m.rowMate[1], -1);
}

TEST(Matching, LongChainNeedsNoRecursion) {
  // Row i contains columns i and i+1; the greedy pass matches row i to i,
  // except that the last column is pushed to the front so the single
  // augmenting path runs the whole chain.
  const int n = 200000;
  BipartiteGraph g(n, n);
  for (int i = 0; i < n; ++i) {
    if (i + 1 < n)
      g.addEdge(i, i + 1);
    g.addEdge(i, i);
  }
  Matching m = maximumMatching(g);
  EXPECT_EQ(m.size, n);
  EXPECT_TRUE(isValidMatching(g, m));
}

TEST(Matching, RandomGraphsAgreeWithBruteForceSize) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    int nr = 1 + rng() % 6, nc = 1 + rng() % 6;
    BipartiteGraph g(nr, nc);
    for (int r = 0; r < nr; ++r)
      for (int c = 0; c < nc; ++c)
        if (rng() % 3 == 0)
          g.addEdge(r, c);
    // Brute force: try every assignment of rows to columns or nothing.
    int best = 0;
    std::vector<int> choice(nr, -1);
    std::function<void(int, int, unsigned)> rec = [&](int r, int got,
                                                      unsigned used) {
      if (r == nr) {
        best = std::max(best, got);
        return;
      }
      rec(r + 1, got, used);
      for (int c : g.rows[r])
        if (!(used & (1u << c)))
          rec(r + 1, got + 1, used | (1u << c));
    };
    rec(0, 0, 0);
    Matching m = maximumMatching(g);
    EXPECT_EQ(m.size, best) << "trial " << trial;
    EXPECT_TRUE(isValidMatching(g, m));
  }
}

TEST(Scc, ComponentsComeDependenciesFirst) {
  // 0 -> 1 -> 2 -> 1, 3 -> 0.
  auto comps = stronglyConnectedComponents({{1}, {2}, {1}, {0}});
  ASSERT_EQ(comps.size(), 3u);
  EXPECT_EQ(comps[0], (std::vector<int>{1, 2}));
  EXPECT_EQ(comps[1], (std::vector<int>{0}));
  EXPECT_EQ(comps[2], (std::vector<int>{3}));
}

TEST(Scc, BltOfTriangularSystemAndAlgebraicLoop) {
  // r0: c0              (solves c0)
  // r1: c0, c1, c2      (with r2 a 2x2 loop in c1, c2)
  // r2: c1, c2
  // r3: c2, c3          (solves c3 last)
  BipartiteGraph g = makeGraph(4, {{0}, {0, 1, 2}, {1, 2}, {2, 3}});
  Matching m = maximumMatching(g);
  ASSERT_EQ(m.size, 4);
  auto blocks = bltBlocks(g, m);
  ASSERT_EQ(blocks.size(), 3u);
  EXPECT_EQ(blocks[0], (std::vector<int>{0}));
  EXPECT_EQ(blocks[1], (std::vector<int>{1, 2}));
  EXPECT_EQ(blocks[2], (std::vector<int>{3}));
}

TEST(Scc, DeepChainIsIterative) {
  const int n = 300000;
  std::vector<std::vector<int>> succ(n);
  for (int i = 1; i < n; ++i)
    succ[i].push_back(i - 1);
  succ[0].push_back(n - 1); // one big cycle
  auto comps = stronglyConnectedComponents(succ);
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_EQ(comps[0].size(), static_cast<size_t>(n));
}

TEST(DulmageMendelsohn, NamesOverAndUnderDeterminedParts) {
  // r0: c0, r1: c0 (both determine only c0), r2: c1, c2 (c1 or c2 free),
  // r3: c3 well determined.
  BipartiteGraph g = makeGraph(4, {{0}, {0}, {1, 2}, {3}});
  Matching m = maximumMatching(g);
  DmDecomposition dm = dulmageMendelsohn(g, m);
  EXPECT_TRUE(dm.singular());
  EXPECT_EQ(dm.over.rows, (std::vector<int>{0, 1}));
  EXPECT_EQ(dm.over.cols, (std::vector<int>{0}));
  EXPECT_EQ(dm.under.rows, (std::vector<int>{2}));
  EXPECT_EQ(dm.under.cols, (std::vector<int>{1, 2}));
  EXPECT_EQ(dm.well.rows, (std::vector<int>{3}));
  EXPECT_EQ(dm.well.cols, (std::vector<int>{3}));
}

TEST(DulmageMendelsohn, SquareNonsingularHasOnlyWellPart) {
  BipartiteGraph g = makeGraph(2, {{0, 1}, {1}});
  DmDecomposition dm = dulmageMendelsohn(g, maximumMatching(g));
  EXPECT_FALSE(dm.singular());
  EXPECT_EQ(dm.well.rows.size(), 2u);
}

TEST(DulmageMendelsohn, ConnectedPiecesSplitIndependentProblems) {
  BipartiteGraph g = makeGraph(3, {{0}, {0}, {1}, {1}, {2}});
  DmDecomposition dm = dulmageMendelsohn(g, maximumMatching(g));
  auto pieces = connectedPieces(g, dm.over);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_EQ(pieces[0].rows, (std::vector<int>{0, 1}));
  EXPECT_EQ(pieces[0].cols, (std::vector<int>{0}));
  EXPECT_EQ(pieces[1].rows, (std::vector<int>{2, 3}));
  EXPECT_EQ(pieces[1].cols, (std::vector<int>{1}));
}

namespace {
// Structural differentiation: each column c contributes c and der(c).
Pantelides::DifferentiateRow structuralHook(Pantelides &p) {
  return [&p](int row) {
    std::vector<int> inc;
    std::vector<int> cols = p.graph().rows[row];
    for (int c : cols) {
      inc.push_back(c);
      inc.push_back(p.derivativeColumn(c));
    }
    std::sort(inc.begin(), inc.end());
    inc.erase(std::unique(inc.begin(), inc.end()), inc.end());
    return inc;
  };
}
} // namespace

TEST(Pantelides, CartesianPendulumFirstOrder) {
  // Columns: x y u v lam | x' y' u' v'  (5..8)
  enum { X, Y, U, V, L, DX, DY, DU, DV };
  BipartiteGraph g = makeGraph(9, {
                                      {DX, U},       // x' = u
                                      {DY, V},       // y' = v
                                      {DU, L, X},    // u' = -lam x
                                      {DV, L, Y},    // v' = -lam y - g
                                      {X, Y},        // x^2 + y^2 = L^2
                                  });
  Pantelides p(g, {DX, DY, DU, DV, -1, -1, -1, -1, -1});
  auto res = p.run(structuralHook(p));
  ASSERT_EQ(res.status, Pantelides::Status::Ok);
  EXPECT_EQ(p.timesDifferentiated(0), 1);
  EXPECT_EQ(p.timesDifferentiated(1), 1);
  EXPECT_EQ(p.timesDifferentiated(2), 0);
  EXPECT_EQ(p.timesDifferentiated(3), 0);
  EXPECT_EQ(p.timesDifferentiated(4), 2);
  // Highest orders: x'' and y'' exist, lam stays order 0.
  EXPECT_GE(p.varDiff()[DX], 0);
  EXPECT_GE(p.varDiff()[DY], 0);
  EXPECT_EQ(p.varDiff()[L], -1);
  EXPECT_EQ(p.matching().size, 5); // the highest-order rows, all matched
  EXPECT_EQ(p.graph().numRows(), 9); // 5 + 1 + 1 + 2
}

TEST(Pantelides, PendulumSecondOrderNeedsNoFirstOrderForm) {
  enum { X, Y, L, DX, DY, DDX, DDY };
  BipartiteGraph g = makeGraph(7, {
                                      {DDX, L, X},
                                      {DDY, L, Y},
                                      {X, Y},
                                  });
  Pantelides p(g, {DX, DY, -1, DDX, DDY, -1, -1});
  auto res = p.run(structuralHook(p));
  ASSERT_EQ(res.status, Pantelides::Status::Ok);
  EXPECT_EQ(p.timesDifferentiated(0), 0);
  EXPECT_EQ(p.timesDifferentiated(1), 0);
  EXPECT_EQ(p.timesDifferentiated(2), 2);
  EXPECT_EQ(p.graph().numRows(), 5);
}

TEST(Pantelides, IndexOneSystemIsLeftAlone) {
  enum { X, Z, DX };
  BipartiteGraph g = makeGraph(3, {{DX, Z}, {Z, X}});
  Pantelides p(g, {DX, -1, -1});
  ASSERT_EQ(p.run(structuralHook(p)).status, Pantelides::Status::Ok);
  EXPECT_EQ(p.graph().numRows(), 2);
  EXPECT_EQ(p.timesDifferentiated(1), 0);
}

TEST(Pantelides, StructurallySingularIsReportedNotLooped) {
  // Two equations in x only, and y in none: Pantelides would never end.
  enum { X, Y, DX };
  BipartiteGraph g = makeGraph(3, {{DX, X}, {X}});
  Pantelides p(g, {DX, -1, -1});
  auto res = p.run(structuralHook(p));
  EXPECT_EQ(res.status, Pantelides::Status::StructurallySingular);
  EXPECT_EQ(res.merged.size, 1);
  DmDecomposition dm =
      dulmageMendelsohn(res.mergedGraph, res.merged, res.mergedCols);
  EXPECT_EQ(dm.over.rows, (std::vector<int>{0, 1}));
  EXPECT_EQ(dm.over.cols, (std::vector<int>{X}));
  EXPECT_EQ(dm.under.cols, (std::vector<int>{Y}));
}

TEST(Pantelides, MattssonSoderlindExample) {
  // y1 + y2 = u1; y1 + y2 + y3 = u2; y1 + y3' + y4 = u3;
  // 2 y1'' + y2'' + y3'' + y4' = u4. Differentiations: 2, 2, 1, 0.
  enum { Y1, Y2, Y3, Y4, D1, D2, D3, D4, DD1, DD2, DD3 };
  BipartiteGraph g = makeGraph(11, {
                                       {Y1, Y2},
                                       {Y1, Y2, Y3},
                                       {Y1, D3, Y4},
                                       {DD1, DD2, DD3, D4},
                                   });
  Pantelides p(g, {D1, D2, D3, D4, DD1, DD2, DD3, -1, -1, -1, -1});
  ASSERT_EQ(p.run(structuralHook(p)).status, Pantelides::Status::Ok);
  EXPECT_EQ(p.timesDifferentiated(0), 2);
  EXPECT_EQ(p.timesDifferentiated(1), 2);
  EXPECT_EQ(p.timesDifferentiated(2), 1);
  EXPECT_EQ(p.timesDifferentiated(3), 0);
}

TEST(Pantelides, DoublePendulumChain) {
  // Two bodies on rods: body 1 hangs from the origin, body 2 from body 1.
  enum { X1, Y1, U1, V1, L1, X2, Y2, U2, V2, L2,
         DX1, DY1, DU1, DV1, DX2, DY2, DU2, DV2 };
  // Row order matters: the second constraint comes before the second
  // body's kinematic rows, which its differentiation differentiates too.
  BipartiteGraph g = makeGraph(18, {
      {DX1, U1}, {DY1, V1},
      {DU1, L1, X1, L2, X2}, {DV1, L1, Y1, L2, Y2},
      {X1, Y1},
      {X1, X2, Y1, Y2},
      {DU2, L2, X1, X2}, {DV2, L2, Y1, Y2},
      {DX2, U2}, {DY2, V2},
  });
  std::vector<int> vd(18, -1);
  vd[X1] = DX1; vd[Y1] = DY1; vd[U1] = DU1; vd[V1] = DV1;
  vd[X2] = DX2; vd[Y2] = DY2; vd[U2] = DU2; vd[V2] = DV2;
  Pantelides p(g, vd);
  ASSERT_EQ(p.run(structuralHook(p)).status, Pantelides::Status::Ok);
  EXPECT_EQ(p.timesDifferentiated(4), 2);
  EXPECT_EQ(p.timesDifferentiated(5), 2);
  EXPECT_EQ(p.timesDifferentiated(0), 1);
  EXPECT_EQ(p.timesDifferentiated(8), 1);
  EXPECT_EQ(p.timesDifferentiated(9), 1);
  EXPECT_EQ(p.timesDifferentiated(2), 0);
  EXPECT_EQ(p.timesDifferentiated(6), 0);
  EXPECT_EQ(p.graph().numRows(), 10 + 2 + 2 + 4);
}
