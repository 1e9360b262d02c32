// Evaluation: exact values, laziness of `if`, memoization on shared DAGs,
// and domain errors that name the failing subexpression.
#include "ir/Evaluate.h"
#include "ir/Print.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace ldae::ir;
using ldae::Expected;

namespace {

struct Names : NameResolver {
  std::string variableName(VarId v) const override {
    return v == 2 ? "r1.v" : std::string(1, "xy"[v]);
  }
  std::string parameterName(ParamId) const override { return "k"; }
};

class Eval : public ::testing::Test {
protected:
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), r = c.var(2);
  double vx = 2, vy = 3, vr = 5;
  Names names;

  Expected<double> run(ExprRef e) {
    EvalEnv env;
    env.time = 0.5;
    env.variable = [&](VarKey k) {
      double v[] = {vx, vy, vr};
      return v[k.var] + 100 * k.order;
    };
    env.parameter = [](ParamId) { return 10.0; };
    return evaluate(e, env, &names);
  }
  std::string errorOf(ExprRef e) {
    auto v = run(e);
    return v ? "no error, value " + printNumber(*v) : v.error();
  }
};

TEST_F(Eval, Values) {
  EXPECT_EQ(*run(c.add(x, y)), 5);
  EXPECT_EQ(*run(c.div(x, y)), 2.0 / 3);
  EXPECT_EQ(*run(c.mul(c.param(0), c.time())), 5);
  EXPECT_EQ(*run(c.var(0, 1)), 102);
  EXPECT_EQ(*run(c.pre(1)), 3); // defaults to the variable's value
  EXPECT_EQ(*run(c.call(FuncKind::Mod, c.neg(x), y)), 1);
  EXPECT_EQ(*run(c.call(FuncKind::Atan2, x, y)), std::atan2(2, 3));
  EXPECT_EQ(*run(c.compare(CompareKind::Ne, x, y)), 1);
  EXPECT_EQ(*run(c.logicalNot(c.compare(CompareKind::Ne, x, y))), 0);
  EXPECT_EQ(*run(c.call(FuncKind::Sign, c.sub(x, y))), -1);
  EXPECT_EQ(*run(c.pow(c.neg(x), c.constant(3))), -8);
}

TEST_F(Eval, IfEvaluatesOnlyTheChosenBranch) {
  vx = -1;
  ExprRef e = c.ifThenElse(c.compare(CompareKind::Gt, x, c.zero()),
                           c.call(FuncKind::Log, x), c.constant(7));
  EXPECT_EQ(*run(e), 7);
  // and/or short-circuit the same way.
  ExprRef guard = c.logicalAnd(
      c.compare(CompareKind::Gt, x, c.zero()),
      c.compare(CompareKind::Gt, c.call(FuncKind::Log, x), c.zero()));
  EXPECT_EQ(*run(guard), 0);
}

TEST_F(Eval, SharedDagIsMemoized) {
  // 2^200 paths, 400 nodes: only memoization makes this finish.
  ExprRef e = x;
  for (int i = 0; i < 200; ++i)
    e = c.mul(c.call(FuncKind::Cos, e), c.call(FuncKind::Sin, e));
  double expect = vx;
  for (int i = 0; i < 200; ++i)
    expect = std::cos(expect) * std::sin(expect);
  EXPECT_EQ(*run(e), expect);
}

TEST_F(Eval, DomainErrorsNameTheSubexpression) {
  vx = 0.5;
  ExprRef one = c.one();
  EXPECT_EQ(errorOf(c.add(y, c.call(FuncKind::Log, c.sub(x, one)))),
            "logarithm of non-positive value -0.5 in 'log(x - 1)'");
  EXPECT_EQ(errorOf(c.call(FuncKind::Log10, c.sub(x, x))),
            "logarithm of non-positive value 0 in 'log10(0)'");
  EXPECT_EQ(errorOf(c.call(FuncKind::Sqrt, c.sub(x, y))),
            "square root of negative value -2.5 in 'sqrt(x - y)'");
  EXPECT_EQ(errorOf(c.mul(x, c.div(y, c.sub(r, c.constant(5))))),
            "division by zero in '1 / ('r1.v' - 5)'");
  EXPECT_EQ(errorOf(c.call(FuncKind::Asin, y)),
            "argument 3 outside [-1, 1] in 'asin(y)'");
  EXPECT_EQ(errorOf(c.call(FuncKind::Acos, c.neg(y))),
            "argument -3 outside [-1, 1] in 'acos(-y)'");
  EXPECT_EQ(
      errorOf(c.pow(c.sub(x, y), c.constant(0.5))),
      "negative base -2.5 with non-integer exponent 0.5 in '(x - y)^0.5'");
  EXPECT_EQ(errorOf(c.pow(c.sub(r, c.constant(5)), c.constant(-1.5))),
            "division by zero in '1 / ('r1.v' - 5)^1.5'");
  EXPECT_EQ(errorOf(c.call(FuncKind::Mod, y, c.sub(r, c.constant(5)))),
            "modulo by zero in 'mod(y, 'r1.v' - 5)'");
  EXPECT_EQ(errorOf(c.div(one, c.zero())), "division by zero in '1 / 0'");
}

TEST(ApplyFunc, NaNOutsideDomain) {
  EXPECT_TRUE(std::isnan(applyFunc(FuncKind::Log, 0)));
  EXPECT_TRUE(std::isnan(applyFunc(FuncKind::Sqrt, -1e-300)));
  EXPECT_TRUE(std::isnan(applyFunc(FuncKind::Acos, 1.0000001)));
  EXPECT_TRUE(std::isnan(applyFunc(FuncKind::Mod, 3, 0)));
  EXPECT_EQ(applyFunc(FuncKind::Mod, 7.5, -2), -0.5);
  EXPECT_EQ(applyFunc(FuncKind::Sign, 0), 0);
  EXPECT_EQ(applyFunc(FuncKind::Max, 1, 2), 2);
  EXPECT_EQ(applyFunc(FuncKind::Ceil, -1.5), -1);
}

} // namespace
