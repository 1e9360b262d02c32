// Substitution (memoized, re-simplifying) and the read-only queries.
#include "ir/Print.h"
#include "ir/Query.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <gtest/gtest.h>

using namespace ldae::ir;

namespace {

TEST(Substitute, ReplacesAndSimplifies) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), p = c.param(0);
  ExprRef e = c.add(c.mul(p, x), c.call(FuncKind::Sin, y));
  Substitution s(c);
  s.set(x, c.neg(y));
  s.set(p, c.constant(2));
  EXPECT_EQ(printLsd(s.apply(e)), "sin(v1) - 2 * v1");
  s.set(y, c.zero());
  // Simultaneous: the replacement of x is not rewritten again.
  EXPECT_EQ(printLsd(s.apply(e)), "-2 * v1"); // memo cleared by set
  // A replaced node is not entered: x inside the replacement stays.
  Substitution t(c);
  t.set(x, c.add(x, c.one()));
  EXPECT_EQ(printLsd(t.apply(c.mul(x, x))), "(v0 + 1)^2");
}

TEST(Substitute, SharedDagRewrittenOnce) {
  ExprContext c;
  ExprRef x = c.var(0), e = x;
  for (int i = 0; i < 100000; ++i) // deep: no recursion allowed
    e = c.add(c.call(FuncKind::Sin, e), x);
  Substitution s(c);
  s.set(x, c.var(1));
  ExprRef r = s.apply(e);
  EXPECT_FALSE(dependsOn(r, {0, 0}));
  EXPECT_TRUE(dependsOn(r, {1, 0}));
  EXPECT_EQ(dagSize(r), dagSize(e));
}

TEST(Substitute, RebuildKeepsKindAndSimplifies) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  ExprRef cmp = c.compare(CompareKind::Le, x, y);
  ExprRef ops[] = {c.one(), c.constant(2)};
  EXPECT_EQ(rebuild(c, cmp, ops), c.one());
  ExprRef f = c.call(FuncKind::Atan2, x, y);
  ExprRef swapped[] = {y, x};
  EXPECT_EQ(rebuild(c, f, swapped), c.call(FuncKind::Atan2, y, x));
  EXPECT_EQ(rebuild(c, x, {}), x);
}

TEST(Query, VariablesParametersOrders) {
  ExprContext c;
  ExprRef x = c.var(0), dx = c.var(0, 1), ddy = c.var(1, 2);
  ExprRef e =
      c.add(c.mul(c.param(3), dx), c.call(FuncKind::Exp, c.sub(ddy, x)));
  e = c.add(e, c.mul(c.param(1), c.pre(2)));
  std::vector<VarKey> expect = {{0, 0}, {0, 1}, {1, 2}};
  EXPECT_EQ(freeVariables(e), expect);
  EXPECT_EQ(freeParameters(e), (std::vector<ParamId>{1, 3}));
  EXPECT_TRUE(dependsOn(e, {1, 2}));
  EXPECT_FALSE(dependsOn(e, {1, 1}));
  EXPECT_FALSE(dependsOnAnyOrder(e, 2)); // pre(v2) is not v2
  EXPECT_TRUE(dependsOnAnyOrder(e, 1));
  EXPECT_EQ(maxOrder(e, 0), 1);
  EXPECT_EQ(maxOrder(e, 1), 2);
  EXPECT_EQ(maxOrder(e, 5), -1);
  EXPECT_FALSE(dependsOnTime(e));
  EXPECT_TRUE(dependsOnTime(c.add(e, c.time())));
}

TEST(Query, TopologicalOrderAndSize) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  ExprRef s = c.call(FuncKind::Sin, x);
  ExprRef a = c.mul(s, y), b = c.add(s, y);
  ExprRef roots[] = {a, b};
  std::vector<ExprRef> order = topologicalOrder(roots);
  EXPECT_EQ(order.size(), 5u); // x, sin, y, a, b
  auto pos = [&](ExprRef e) {
    return std::find(order.begin(), order.end(), e) - order.begin();
  };
  for (ExprRef e : order)
    for (ExprRef op : e->operands())
      EXPECT_LT(pos(op), pos(e));
  EXPECT_EQ(dagSize(a), 4u);
  ExprRef chain = x;
  for (int i = 0; i < 300; ++i)
    chain = c.mul(c.call(FuncKind::Cos, chain), chain);
  EXPECT_EQ(dagSize(chain), 601u);
}

} // namespace
