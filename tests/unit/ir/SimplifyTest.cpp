// Table-driven tests of the simplifying builders: each row builds an
// expression through ExprContext and states the exact lsd text it must
// simplify to, including the cases that must NOT simplify because that
// would change the value where the input is defined (docs/ir.md).
#include "ir/ExprContext.h"
#include "ir/Print.h"

#include <functional>
#include <gtest/gtest.h>

using namespace ldae::ir;

namespace {

struct Names : NameResolver {
  std::string variableName(VarId v) const override {
    return std::string(1, "xyzuvw"[v]);
  }
  std::string parameterName(ParamId p) const override {
    return std::string(1, "abc"[p]);
  }
};

struct Row {
  const char *name;
  std::function<ExprRef(ExprContext &, ExprRef x, ExprRef y, ExprRef z)> build;
  const char *expected;
  friend void PrintTo(const Row &row, std::ostream *os) { *os << row.name; }
};

class SimplifyTable : public ::testing::TestWithParam<Row> {};

TEST_P(SimplifyTable, PrintsExpected) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), z = c.var(2);
  Names names;
  const Row &row = GetParam();
  EXPECT_EQ(printLsd(row.build(c, x, y, z), &names), row.expected) << row.name;
}

ExprRef k(ExprContext &c, double v) { return c.constant(v); }

// clang-format off
const Row rows[] = {
    // Constant folding.
    {"fold-add", [](auto &c, auto, auto, auto) { return c.add(k(c, 2), k(c, 3)); }, "5"},
    {"fold-mul", [](auto &c, auto, auto, auto) { return c.mul(k(c, 2), k(c, 3)); }, "6"},
    {"fold-pow", [](auto &c, auto, auto, auto) { return c.pow(k(c, 2), k(c, 10)); }, "1024"},
    {"fold-div", [](auto &c, auto, auto, auto) { return c.div(k(c, 1), k(c, 10)); }, "0.1"},
    {"fold-sin", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Sin, k(c, 0)); }, "0"},
    {"fold-atan2", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Atan2, k(c, 0), k(c, 1)); }, "0"},
    {"fold-mod", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Mod, k(c, -7), k(c, 3)); }, "2"},
    // Folding never hides a domain error: these stay symbolic.
    {"no-fold-log0", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Log, k(c, 0)); }, "log(0)"},
    {"no-fold-sqrt-neg", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Sqrt, k(c, -1)); }, "sqrt(-1)"},
    {"no-fold-div0", [](auto &c, auto, auto, auto) { return c.div(k(c, 1), k(c, 0)); }, "1 / 0"},
    {"no-fold-neg-base", [](auto &c, auto, auto, auto) { return c.pow(k(c, -8), k(c, 1.0 / 3)); }, "(-8)^0.3333333333333333"},
    {"no-fold-mod0", [](auto &c, auto, auto, auto) { return c.call(FuncKind::Mod, k(c, 1), k(c, 0)); }, "mod(1, 0)"},
    // Neutral and absorbing elements.
    {"x+0", [](auto &c, auto x, auto, auto) { return c.add(x, c.zero()); }, "x"},
    {"x*1", [](auto &c, auto x, auto, auto) { return c.mul(x, c.one()); }, "x"},
    {"x^1", [](auto &c, auto x, auto, auto) { return c.pow(x, c.one()); }, "x"},
    {"x^0", [](auto &c, auto x, auto, auto) { return c.pow(x, c.zero()); }, "1"},
    {"0*x", [](auto &c, auto x, auto, auto) { return c.mul(c.zero(), x); }, "0"},
    {"0*sin(x)", [](auto &c, auto x, auto, auto) { return c.mul(c.zero(), c.call(FuncKind::Sin, x)); }, "0"},
    {"1^x", [](auto &c, auto x, auto, auto) { return c.pow(c.one(), x); }, "1"},
    {"0^2", [](auto &c, auto x, auto, auto) { return c.pow(c.zero(), k(c, 2)); }, "0"},
    // ... but not when the other factor may be undefined or infinite.
    {"0*log(x)", [](auto &c, auto x, auto, auto) { return c.mul(c.zero(), c.call(FuncKind::Log, x)); }, "0 * log(x)"},
    {"0/x", [](auto &c, auto x, auto, auto) { return c.div(c.zero(), x); }, "0 / x"},
    {"log(x)^0", [](auto &c, auto x, auto, auto) { return c.pow(c.call(FuncKind::Log, x), c.zero()); }, "log(x)^0"},
    {"0*x^0.5", [](auto &c, auto x, auto, auto) { return c.mul(c.zero(), c.pow(x, k(c, 0.5))); }, "0 * x^0.5"},
    // Flattening and like terms.
    {"flatten", [](auto &c, auto x, auto y, auto z) { return c.add(c.add(x, y), c.add(z, x)); }, "2 * x + y + z"},
    {"2x+3x", [](auto &c, auto x, auto, auto) { return c.add(c.mul(k(c, 2), x), c.mul(k(c, 3), x)); }, "5 * x"},
    {"x-x", [](auto &c, auto x, auto, auto) { return c.sub(x, x); }, "0"},
    {"a-a", [](auto &c, auto x, auto y, auto) { ExprRef a = c.add(c.mul(x, y), c.call(FuncKind::Sin, x)); return c.sub(a, a); }, "0"},
    {"(x+y)-x", [](auto &c, auto x, auto y, auto) { return c.sub(c.add(x, y), x); }, "y"},
    {"x+1-1", [](auto &c, auto x, auto, auto) { return c.sub(c.add(x, c.one()), c.one()); }, "x"},
    {"xy-yx", [](auto &c, auto x, auto y, auto) { return c.sub(c.mul(x, y), c.mul(y, x)); }, "0"},
    {"log(x)-log(x) keeps", [](auto &c, auto x, auto, auto) { ExprRef l = c.call(FuncKind::Log, x); return c.sub(l, l); }, "0 * log(x)"},
    // Powers.
    {"x*x", [](auto &c, auto x, auto, auto) { return c.mul(x, x); }, "x^2"},
    {"x^2*x^3", [](auto &c, auto x, auto, auto) { return c.mul(c.pow(x, k(c, 2)), c.pow(x, k(c, 3))); }, "x^5"},
    {"x/x stays", [](auto &c, auto x, auto, auto) { return c.div(x, x); }, "x / x"},
    {"x^2/x stays", [](auto &c, auto x, auto, auto) { return c.div(c.mul(x, x), x); }, "x^2 / x"},
    {"1/x/x", [](auto &c, auto x, auto, auto) { return c.div(c.div(c.one(), x), x); }, "1 / x^2"},
    {"x^0.5*x^0.5 stays", [](auto &c, auto x, auto, auto) { ExprRef s = c.pow(x, k(c, 0.5)); return c.mul(s, s); }, "(x^0.5)^2"},
    {"(x^2)^3", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, 2)), k(c, 3)); }, "x^6"},
    {"(x^-1)^2", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, -1)), k(c, 2)); }, "1 / x^2"},
    {"(x^-1)^-1 stays", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, -1)), k(c, -1)); }, "1 / (1 / x)"},
    {"(x^2)^0.5 stays", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, 2)), k(c, 0.5)); }, "(x^2)^0.5"},
    {"(x^0.5)^2 stays", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, 0.5)), k(c, 2)); }, "(x^0.5)^2"},
    {"(x^0.5)^3", [](auto &c, auto x, auto, auto) { return c.pow(c.pow(x, k(c, 0.5)), k(c, 3)); }, "x^1.5"},
    {"2*3*x", [](auto &c, auto x, auto, auto) { ExprRef f[] = {k(c, 2), x, k(c, 3)}; return c.mul(f); }, "6 * x"},
    // Negation and subtraction.
    {"--x", [](auto &c, auto x, auto, auto) { return c.neg(c.neg(x)); }, "x"},
    {"-x", [](auto &c, auto x, auto, auto) { return c.neg(x); }, "-x"},
    {"x-y", [](auto &c, auto x, auto y, auto) { return c.sub(x, y); }, "x - y"},
    {"-(x+y)", [](auto &c, auto x, auto y, auto) { return c.neg(c.add(x, y)); }, "-x - y"},
    {"x/2", [](auto &c, auto x, auto, auto) { return c.div(x, k(c, 2)); }, "x / 2"},
    {"x/y", [](auto &c, auto x, auto y, auto) { return c.div(x, y); }, "x / y"},
    {"-x/y", [](auto &c, auto x, auto y, auto) { return c.neg(c.div(x, y)); }, "-x / y"},
    {"x-2y", [](auto &c, auto x, auto y, auto) { return c.sub(x, c.mul(k(c, 2), y)); }, "x - 2 * y"},
    {"y-x", [](auto &c, auto x, auto y, auto) { return c.sub(y, x); }, "y - x"},
    // Conditionals and logic.
    {"if-true", [](auto &c, auto x, auto y, auto) { return c.ifThenElse(c.one(), x, y); }, "x"},
    {"if-false", [](auto &c, auto x, auto y, auto) { return c.ifThenElse(c.zero(), x, y); }, "y"},
    {"if-same", [](auto &c, auto x, auto y, auto) { return c.ifThenElse(c.compare(CompareKind::Lt, x, y), x, x); }, "x"},
    {"if-not", [](auto &c, auto x, auto y, auto z) { return c.ifThenElse(c.logicalNot(c.compare(CompareKind::Lt, x, y)), y, z); }, "if x >= y then y else z"},
    {"if-not-and", [](auto &c, auto x, auto y, auto z) { ExprRef a = c.compare(CompareKind::Lt, x, y); ExprRef b = c.compare(CompareKind::Lt, y, z); return c.ifThenElse(c.logicalNot(c.logicalAnd(a, b)), y, z); }, "if x < y and y < z then z else y"},
    {"cmp-const", [](auto &c, auto, auto, auto) { return c.compare(CompareKind::Le, k(c, 1), k(c, 2)); }, "1"},
    {"cmp-same", [](auto &c, auto x, auto, auto) { return c.compare(CompareKind::Lt, x, x); }, "0"},
    {"and-true", [](auto &c, auto x, auto y, auto) { return c.logicalAnd(c.one(), c.compare(CompareKind::Gt, x, y)); }, "x > y"},
    {"and-false", [](auto &c, auto x, auto y, auto) { return c.logicalAnd(c.zero(), c.compare(CompareKind::Gt, x, y)); }, "0"},
    {"or-true", [](auto &c, auto x, auto y, auto) { return c.logicalOr(c.compare(CompareKind::Gt, x, y), c.one()); }, "1"},
    {"not-not", [](auto &c, auto x, auto y, auto) { ExprRef a = c.compare(CompareKind::Gt, x, y); ExprRef b = c.compare(CompareKind::Gt, y, x); return c.logicalNot(c.logicalNot(c.logicalAnd(b, a))); }, "x > y and y > x"},
    {"not-cmp", [](auto &c, auto x, auto y, auto) { return c.logicalNot(c.compare(CompareKind::Lt, x, y)); }, "x >= y"},
    {"min-same", [](auto &c, auto x, auto, auto) { return c.call(FuncKind::Min, x, x); }, "x"},
    {"abs-abs", [](auto &c, auto x, auto, auto) { return c.call(FuncKind::Abs, c.call(FuncKind::Abs, x)); }, "abs(x)"},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Rules, SimplifyTable, ::testing::ValuesIn(rows));

} // namespace
