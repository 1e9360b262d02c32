// Hash-consing: structurally equal expressions are one node, whatever the
// order commutative operands were given in; ids are deterministic.
#include "ir/ExprContext.h"
#include "ir/Print.h"

#include <gtest/gtest.h>
#include <vector>

using namespace ldae::ir;

namespace {

ExprRef sample(ExprContext &c) {
  ExprRef x = c.var(0), y = c.var(1), p = c.param(0);
  ExprRef s = c.call(FuncKind::Sin, c.mul(p, x));
  return c.ifThenElse(c.compare(CompareKind::Gt, x, y),
                      c.add(s, c.pow(y, c.constant(2))), c.div(s, y));
}

TEST(HashCons, SameExpressionTwiceIsOneNode) {
  ExprContext c;
  ExprRef a = sample(c);
  size_t nodes = c.size();
  ExprRef b = sample(c);
  EXPECT_EQ(a, b);
  EXPECT_EQ(c.size(), nodes); // nothing new was made
}

TEST(HashCons, CommutativeOperandsInAnyOrder) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), z = c.var(2);
  ExprRef s = c.call(FuncKind::Cos, z);
  ExprRef abc[] = {x, y, s}, cab[] = {s, x, y}, bca[] = {y, s, x};
  EXPECT_EQ(c.add(abc), c.add(cab));
  EXPECT_EQ(c.add(abc), c.add(bca));
  EXPECT_EQ(c.mul(abc), c.mul(bca));
  EXPECT_EQ(c.add(c.add(x, y), s), c.add(x, c.add(s, y)));
  EXPECT_EQ(c.mul(c.mul(x, y), c.constant(2)),
            c.mul(c.constant(2), c.mul(y, x)));
  ExprRef cx = c.compare(CompareKind::Lt, x, y),
          cy = c.compare(CompareKind::Lt, y, z);
  EXPECT_EQ(c.logicalAnd(cx, cy), c.logicalAnd(cy, cx));
  EXPECT_EQ(c.logicalOr(cx, cy), c.logicalOr(cy, cx));
  // Coefficients folded in any order give the same bits.
  ExprRef t1[] = {c.mul(c.constant(0.1), x), c.mul(c.constant(0.2), x),
                  c.mul(c.constant(0.3), x)};
  ExprRef t2[] = {t1[2], t1[0], t1[1]};
  EXPECT_EQ(c.add(t1), c.add(t2));
}

TEST(HashCons, PopularOperandsStayUnique) {
  // A node used by many others: its first users are uniqued in its own
  // list, the rest in the global table; both must find them again.
  ExprContext c;
  std::vector<ExprRef> vars;
  for (unsigned i = 0; i < 200; ++i)
    vars.push_back(c.var(i));
  ExprRef hub = c.call(FuncKind::Sin, vars[0]); // newest: the pivot below
  std::vector<ExprRef> first;
  for (ExprRef v : vars) {
    first.push_back(c.mul(hub, v));
    first.push_back(c.call(FuncKind::Atan2, v, hub));
  }
  size_t nodes = c.size();
  for (size_t i = 0; i < vars.size(); ++i) {
    EXPECT_EQ(c.mul(vars[i], hub), first[2 * i]);
    EXPECT_EQ(c.call(FuncKind::Atan2, vars[i], hub), first[2 * i + 1]);
  }
  EXPECT_EQ(c.size(), nodes);
}

TEST(HashCons, CanonicalOrderHasConstantFirst) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  ExprRef m = c.mul(c.mul(y, x), c.constant(3));
  ASSERT_EQ(m->kind(), ExprKind::Mul);
  ASSERT_EQ(m->numOperands(), 3u);
  EXPECT_TRUE(m->operand(0)->isConstant(3));
  EXPECT_EQ(m->operand(1), x);
  EXPECT_EQ(m->operand(2), y);
  ExprRef s = c.add(y, c.add(c.constant(1), x));
  EXPECT_TRUE(s->operand(0)->isConstant(1));
  EXPECT_LT(s->operand(1)->id(), s->operand(2)->id());
}

TEST(HashCons, DistinctThingsStayDistinct) {
  ExprContext c;
  EXPECT_NE(c.var(0), c.var(0, 1));
  EXPECT_NE(c.var(0), c.var(1));
  EXPECT_NE(c.var(0), c.pre(0));
  EXPECT_NE(c.var(0), c.param(0));
  EXPECT_NE(c.call(FuncKind::Sin, c.var(0)), c.call(FuncKind::Cos, c.var(0)));
  EXPECT_NE(c.compare(CompareKind::Lt, c.var(0), c.var(1)),
            c.compare(CompareKind::Le, c.var(0), c.var(1)));
  EXPECT_NE(c.constant(1), c.constant(1 + 1e-16 * 2));
  EXPECT_EQ(c.constant(-0.0), c.constant(0.0));
  EXPECT_EQ(c.time(), c.time());
}

TEST(HashCons, IdsAreDeterministic) {
  ExprContext c1, c2;
  ExprRef a = sample(c1), b = sample(c2);
  EXPECT_EQ(a->id(), b->id());
  EXPECT_EQ(a->hash(), b->hash());
  EXPECT_EQ(printDebug(a), printDebug(b));
  EXPECT_EQ(c1.size(), c2.size());
  EXPECT_GT(c1.memoryBytes(), 0u);
}

} // namespace
