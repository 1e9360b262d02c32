// Printing: numbers read back exactly, lsd text with Modelica precedence and
// the canonical forms turned back into `a - b`, `-a`, `a / b`; quoted flat
// names; the debug form.
#include "ir/Print.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <gtest/gtest.h>
#include <random>

using namespace ldae::ir;

namespace {

TEST(PrintNumber, ShortestRoundTrip) {
  EXPECT_EQ(printNumber(0.1), "0.1");
  EXPECT_EQ(printNumber(1e-300), "1e-300");
  EXPECT_EQ(printNumber(100), "100");
  EXPECT_EQ(printNumber(-2.5), "-2.5");
  EXPECT_EQ(printNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(printNumber(1.0 / 3), "0.3333333333333333");
  EXPECT_EQ(printNumber(1e20), "1e+20");
  EXPECT_EQ(printNumber(-0.0), "0");
  std::mt19937_64 rng(3);
  for (int i = 0; i < 10000; ++i) {
    uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v))
      continue;
    std::string s = printNumber(v);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
}

TEST(PrintIdentifier, QuotesFlatNames) {
  EXPECT_EQ(printIdentifier("x_1"), "x_1");
  EXPECT_EQ(printIdentifier("r1.v"), "'r1.v'");
  EXPECT_EQ(printIdentifier("m[2].s"), "'m[2].s'");
  EXPECT_EQ(printIdentifier("end"), "'end'");
  EXPECT_EQ(printIdentifier("it's"), "'it\\'s'");
  EXPECT_EQ(printIdentifier("1x"), "'1x'");
  EXPECT_EQ(printString("N.m"), "\"N.m\"");
  EXPECT_EQ(printString("a\"b\\"), "\"a\\\"b\\\\\"");
}

struct Names : NameResolver {
  std::string variableName(VarId v) const override {
    const char *n[] = {"x", "y", "z", "r1.v", "m[2].s"};
    return n[v];
  }
  std::string parameterName(ParamId p) const override {
    return p == 0 ? "L" : "k";
  }
};

class Print : public ::testing::Test {
protected:
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), z = c.var(2), rv = c.var(3),
          ms = c.var(4), L = c.param(0), k = c.param(1);
  Names names;
  std::string lsd(ExprRef e) { return printLsd(e, &names); }
  ExprRef num(double v) { return c.constant(v); }
  ExprRef sq(ExprRef e) { return c.pow(e, num(2)); }
  ExprRef lt(ExprRef a, ExprRef b) { return c.compare(CompareKind::Lt, a, b); }
};

TEST_F(Print, LeavesAndDerivatives) {
  EXPECT_EQ(lsd(c.var(0, 1)), "der(x)");
  EXPECT_EQ(lsd(c.var(0, 2)), "der(der(x))");
  EXPECT_EQ(lsd(c.var(3, 1)), "der('r1.v')");
  EXPECT_EQ(lsd(c.pre(4)), "pre('m[2].s')");
  EXPECT_EQ(lsd(c.time()), "time");
  ExprRef d7 = c.var(7, 1);
  EXPECT_EQ(printLsd(c.add(d7, c.param(2))), "der(v7) + p2");
}

TEST_F(Print, Arithmetic) {
  ExprRef xx = sq(x), yy = sq(y), LL = sq(L);
  ExprRef t[] = {xx, yy, c.neg(LL)};
  EXPECT_EQ(lsd(c.add(t)), "x^2 + y^2 - L^2");
  EXPECT_EQ(lsd(c.sub(num(3), x)), "3 - x");
  EXPECT_EQ(lsd(c.sub(c.neg(x), num(1))), "-x - 1");
  EXPECT_EQ(lsd(c.mul(num(-3), x)), "-3 * x");
  EXPECT_EQ(lsd(c.mul(num(0.1), x)), "x / 10");
  EXPECT_EQ(lsd(c.mul(num(0.3), x)), "0.3 * x");
  EXPECT_EQ(lsd(c.mul(c.add(x, y), z)), "z * (x + y)");
  EXPECT_EQ(lsd(c.mul(c.neg(c.add(x, y)), z)), "z * (-x - y)");
  EXPECT_EQ(lsd(c.div(x, c.mul(y, z))), "x / (y * z)");
  EXPECT_EQ(lsd(c.div(x, c.add(y, z))), "x / (y + z)");
  EXPECT_EQ(lsd(c.div(x, sq(y))), "x / y^2");
  EXPECT_EQ(lsd(c.div(c.neg(x), c.mul(num(2), y))), "-x / (2 * y)");
  EXPECT_EQ(lsd(c.pow(c.mul(x, y), num(2))), "(x * y)^2");
  EXPECT_EQ(lsd(c.pow(c.neg(x), num(3))), "(-x)^3");
  EXPECT_EQ(lsd(c.pow(x, c.neg(y))), "x^(-y)");
  EXPECT_EQ(lsd(c.pow(num(2), c.add(x, num(1)))), "2^(x + 1)");
  EXPECT_EQ(lsd(c.pow(x, num(-0.5))), "1 / x^0.5");
  EXPECT_EQ(lsd(sq(c.call(FuncKind::Sin, x))), "sin(x)^2");
  EXPECT_EQ(lsd(c.call(FuncKind::Atan2, y, c.neg(x))), "atan2(y, -x)");
  EXPECT_EQ(lsd(c.mul(k, c.call(FuncKind::Mod, rv, ms))),
            "k * mod('r1.v', 'm[2].s')");
  EXPECT_EQ(lsd(c.sub(x, c.mul(num(2), c.div(y, z)))), "x - 2 * y / z");
}

TEST_F(Print, ConditionalsAndLogic) {
  ExprRef inner = c.ifThenElse(lt(y, num(0)), num(1), num(2));
  EXPECT_EQ(lsd(c.ifThenElse(lt(x, num(0)), inner, num(3))),
            "if x < 0 then (if y < 0 then 1 else 2) else 3");
  EXPECT_EQ(lsd(c.add(num(1), c.ifThenElse(lt(x, y), x, y))),
            "(if x < y then x else y) + 1");
  EXPECT_EQ(lsd(c.add(x, lt(x, y))), "x + (if x < y then 1 else 0)");
  ExprRef a = lt(x, y), b = lt(y, z), d = c.compare(CompareKind::Ne, z, x);
  EXPECT_EQ(lsd(c.logicalOr(c.logicalAnd(a, b), d)),
            "z <> x or x < y and y < z");
  EXPECT_EQ(lsd(c.logicalAnd(c.logicalOr(a, b), d)),
            "z <> x and (x < y or y < z)");
  EXPECT_EQ(lsd(c.logicalNot(c.logicalAnd(a, b))), "not (x < y and y < z)");
  EXPECT_EQ(lsd(c.compare(CompareKind::Ge, c.neg(x), c.add(y, z))),
            "-x >= y + z");
  EXPECT_EQ(
      lsd(c.logicalAnd(c.zero(), c.compare(CompareKind::Gt,
                                           c.call(FuncKind::Log, x), num(0)))),
      "false and log(x) > 0");
}

TEST_F(Print, DebugAndBrief) {
  EXPECT_EQ(printDebug(c.sub(x, y), &names), "(+ x (* -1 y))");
  ExprRef s = c.call(FuncKind::Sin, x);
  ExprRef e = c.add(s, c.mul(s, c.var(1, 2)));
  std::string id = std::to_string(s->id());
  EXPECT_EQ(printDebug(e, &names),
            "(+ #" + id + "=(sin x) (* #" + id + " y'2))");
  ExprRef big = x;
  for (int i = 0; i < 50; ++i)
    big = c.call(FuncKind::Cos, c.add(big, y));
  std::string brief = printLsdBrief(big, &names, 40);
  EXPECT_EQ(brief.size(), 43u);
  EXPECT_EQ(brief.substr(0, 12), "cos(y + cos(");
  EXPECT_EQ(brief.substr(40), "...");
}

} // namespace
