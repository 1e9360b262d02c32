// The jump rule's tables (compiler/passes/JumpPencil.cpp): which slots are
// dummy derivatives of which, and which rows are equations as written,
// filled at the end of build-system.
#include "TestModels.h"

#include "passes/JumpPencil.h"

#include <gtest/gtest.h>

namespace ldae::passtest {

namespace {

int slot(const ir::DaeSystem &sys, const std::string &name) {
  for (size_t u = 0; u < sys.unknowns.size(); ++u)
    if (sys.unknowns[u].name == name)
      return static_cast<int>(u);
  ADD_FAILURE() << "no slot " << name;
  return -2;
}

int count(const std::vector<bool> &v, bool b) {
  return static_cast<int>(std::count(v.begin(), v.end(), b));
}

} // namespace

TEST(JumpPencil, TwoCapacitorsTheDummyAndTheDifferentiatedRow) {
  // 2 v1 = 2 v2 (not an alias: alias elimination would merge the two).
  Builder b("TwoCaps", "caps.lsd");
  auto &c = b.ctx();
  ir::ExprRef C1 = b.param("C1", 1e-3), C2 = b.param("C2", 2e-3);
  ir::ExprRef v1 = b.var("v1", 10), v2 = b.var("v2", 1), i = b.var("i");
  b.eq(c.mul(C1, b.der(v1)), c.neg(i), "C1 * der(v1) = -i");
  b.eq(c.mul(C2, b.der(v2)), i, "C2 * der(v2) = i");
  b.eq(c.mul(c.constant(2), v1), c.mul(c.constant(2), v2), "2 v1 = 2 v2");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const ir::DaeSystem &sys = *run.result.system;
  ASSERT_EQ(sys.dummyOf.size(), 1u);
  ASSERT_EQ(sys.unknowns.size(), 4u);
  ASSERT_EQ(run.result.dummies.size(), 1u);
  const std::string &d = run.result.dummies[0]; // der(v1) or der(v2)
  int dummy = slot(sys, d);
  int of = slot(sys, d == "der(v1)" ? "v1" : "v2");
  for (size_t u = 0; u < 4; ++u)
    EXPECT_EQ(sys.dummyOf[0][u], int(u) == dummy ? of : -1) << u;
  // The three equations as written, then der(2 v1 = 2 v2).
  EXPECT_EQ(sys.originalRow[0],
            (std::vector<bool>{true, true, true, false}));
}

TEST(JumpPencil, PendulumEverySetAndSecondDerivatives) {
  Builder b("Pendulum", "pend.lsd");
  pendulumFirstOrder(b);
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const ir::DaeSystem &sys = *run.result.system;
  const size_t n = sys.unknowns.size();
  ASSERT_EQ(sys.dummyOf.size(), 2u);
  ASSERT_EQ(sys.originalRow.size(), 2u);
  // Set 0 (states v, y; dummies der(u), der(x), der(der(x)), der(der(y))):
  // each dummy is the derivative of the slot one order below.
  const auto &d0 = sys.dummyOf[0];
  EXPECT_EQ(d0[slot(sys, "der(x)")], slot(sys, "x"));
  EXPECT_EQ(d0[slot(sys, "der(u)")], slot(sys, "u"));
  EXPECT_EQ(d0[slot(sys, "der(der(x))")], slot(sys, "der(x)"));
  EXPECT_EQ(d0[slot(sys, "der(der(y))")], slot(sys, "der(y)"));
  EXPECT_EQ(std::count_if(d0.begin(), d0.end(), [](int j) { return j >= 0; }),
            4);
  // Set 1 (states u, x): der(x) is an unknown as written there.
  EXPECT_EQ(sys.dummyOf[1][slot(sys, "der(x)")], -1);
  EXPECT_EQ(sys.dummyOf[1][slot(sys, "der(y)")], slot(sys, "y"));
  // Five equations as written, plus each set's link rows; the constraint's
  // two derivatives and der(x) = u, der(y) = v differentiated are not.
  for (size_t s = 0; s < 2; ++s) {
    ASSERT_EQ(sys.originalRow[s].size(), n);
    EXPECT_EQ(count(sys.originalRow[s], false), 4) << s;
  }
}

TEST(JumpPencil, NoTablesWhereTheyWouldSayNothingOrBeRewritten) {
  // Index 1: no dummy, every row as written.
  Builder b("Decay", "decay.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x", 1), z = b.var("z");
  b.eq(b.der(x), c.neg(z), "der(x) = -z");
  b.eq(z, c.mul(c.constant(2), x), "z = 2 x");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  EXPECT_TRUE(run.result.system->dummyOf.empty());
  // Causalized: the rows are rewritten, the tables would lie.
  Builder p("Pendulum", "pend.lsd");
  pendulumFirstOrder(p);
  passes::PipelineOptions opts;
  Outcome causal = analyze(p, opts);
  ASSERT_TRUE(causal.ok) << causal.messages;
  EXPECT_TRUE(causal.result.system->dummyOf.empty());
  EXPECT_TRUE(causal.result.system->originalRow.empty());
}

TEST(JumpPencil, RestrictKeepsTheTablesOfTheKeptSlots) {
  ir::DaeSystem sys;
  sys.dummyOf = {{-1, -1, -1, 1}};
  sys.originalRow = {{true, true, true, false}};
  // Unknown 2 dropped; rows 3, 0, 1 kept in that order.
  ASSERT_TRUE(passes::restrictJumpPencil(sys, {0, 1, -1, 2}, {{3, 0, 1}}));
  EXPECT_EQ(sys.dummyOf[0], (std::vector<int>{-1, -1, 1}));
  EXPECT_EQ(sys.originalRow[0], (std::vector<bool>{false, true, true}));
  // The dummy's variable dropped: no pencil as written any more.
  EXPECT_FALSE(passes::restrictJumpPencil(sys, {0, -1, 1}, {{0, 1}}));
  EXPECT_TRUE(sys.dummyOf.empty());
  EXPECT_TRUE(sys.originalRow.empty());
}

} // namespace ldae::passtest
