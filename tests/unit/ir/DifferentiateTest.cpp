// The differentiator against numbers: every built-in's partial derivatives
// match central finite differences (Richardson-extrapolated) at random
// points inside its domain and away from kinks; the total time derivative of
// a small expression matches a hand computation; memoization keeps the
// derivative of a shared DAG linear in size.
#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Print.h"
#include "ir/Query.h"

#include <cmath>
#include <functional>
#include <gtest/gtest.h>
#include <random>

using namespace ldae::ir;

namespace {

struct Case {
  const char *name;
  std::function<ExprRef(ExprContext &, ExprRef x, ExprRef y)> build;
  /// Draws a point (x, y) inside the domain, away from kinks.
  std::function<std::pair<double, double>(std::mt19937 &)> point;
  friend void PrintTo(const Case &c, std::ostream *os) { *os << c.name; }
};

double uniform(std::mt19937 &rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

auto box(double lo, double hi) {
  return [=](std::mt19937 &rng) {
    return std::make_pair(uniform(rng, lo, hi), uniform(rng, lo, hi));
  };
}

/// A point whose fractional part (of x, or of x/y) stays inside (0.1, 0.9).
auto awayFromIntegers(bool ratio) {
  return [=](std::mt19937 &rng) {
    double y = uniform(rng, 0.5, 3);
    double q = std::floor(uniform(rng, -4, 4)) + uniform(rng, 0.1, 0.9);
    return std::make_pair(ratio ? q * y : q, y);
  };
}

/// x and y at least 0.1 apart (min, max, comparisons).
auto apart(double lo, double hi) {
  return [=](std::mt19937 &rng) {
    double x = uniform(rng, lo, hi), y = uniform(rng, lo, hi);
    while (std::abs(x - y) < 0.1)
      y = uniform(rng, lo, hi);
    return std::make_pair(x, y);
  };
}

ExprRef unary(ExprContext &c, FuncKind f, ExprRef a) { return c.call(f, a); }

// clang-format off
const Case cases[] = {
    {"sin", [](auto &c, auto x, auto) { return unary(c, FuncKind::Sin, x); }, box(-3, 3)},
    {"cos", [](auto &c, auto x, auto) { return unary(c, FuncKind::Cos, x); }, box(-3, 3)},
    {"tan", [](auto &c, auto x, auto) { return unary(c, FuncKind::Tan, x); }, box(-1.2, 1.2)},
    {"asin", [](auto &c, auto x, auto) { return unary(c, FuncKind::Asin, x); }, box(-0.9, 0.9)},
    {"acos", [](auto &c, auto x, auto) { return unary(c, FuncKind::Acos, x); }, box(-0.9, 0.9)},
    {"atan", [](auto &c, auto x, auto) { return unary(c, FuncKind::Atan, x); }, box(-5, 5)},
    {"atan2", [](auto &c, auto x, auto y) { return c.call(FuncKind::Atan2, y, x); },
     [](std::mt19937 &rng) { return std::make_pair(uniform(rng, 0.2, 2), uniform(rng, -2, 2)); }},
    {"sinh", [](auto &c, auto x, auto) { return unary(c, FuncKind::Sinh, x); }, box(-2, 2)},
    {"cosh", [](auto &c, auto x, auto) { return unary(c, FuncKind::Cosh, x); }, box(-2, 2)},
    {"tanh", [](auto &c, auto x, auto) { return unary(c, FuncKind::Tanh, x); }, box(-2, 2)},
    {"exp", [](auto &c, auto x, auto) { return unary(c, FuncKind::Exp, x); }, box(-3, 3)},
    {"log", [](auto &c, auto x, auto) { return unary(c, FuncKind::Log, x); }, box(0.1, 5)},
    {"log10", [](auto &c, auto x, auto) { return unary(c, FuncKind::Log10, x); }, box(0.1, 5)},
    {"sqrt", [](auto &c, auto x, auto) { return unary(c, FuncKind::Sqrt, x); }, box(0.1, 5)},
    {"abs", [](auto &c, auto x, auto) { return unary(c, FuncKind::Abs, x); },
     [](std::mt19937 &rng) { double x = uniform(rng, 0.1, 3); return std::make_pair(rng() % 2 ? x : -x, 1.0); }},
    {"sign", [](auto &c, auto x, auto y) { return c.mul(unary(c, FuncKind::Sign, x), y); },
     [](std::mt19937 &rng) { double x = uniform(rng, 0.1, 3); return std::make_pair(rng() % 2 ? x : -x, uniform(rng, -2, 2)); }},
    {"min", [](auto &c, auto x, auto y) { return c.call(FuncKind::Min, c.mul(x, y), y); }, apart(-2, 2)},
    {"max", [](auto &c, auto x, auto y) { return c.call(FuncKind::Max, x, c.mul(x, y)); }, apart(-2, 2)},
    {"floor", [](auto &c, auto x, auto y) { return c.add(unary(c, FuncKind::Floor, x), y); }, awayFromIntegers(false)},
    {"ceil", [](auto &c, auto x, auto y) { return c.mul(unary(c, FuncKind::Ceil, x), y); }, awayFromIntegers(false)},
    {"mod", [](auto &c, auto x, auto y) { return c.call(FuncKind::Mod, x, y); }, awayFromIntegers(true)},
    {"pow-general", [](auto &c, auto x, auto y) { return c.pow(x, y); },
     [](std::mt19937 &rng) { return std::make_pair(uniform(rng, 0.2, 3), uniform(rng, -2, 2)); }},
    {"pow-const-exp", [](auto &c, auto x, auto y) { return c.add(c.pow(x, c.constant(3)), c.pow(y, c.constant(-2))); }, box(0.3, 2)},
    {"pow-half", [](auto &c, auto x, auto) { return c.pow(x, c.constant(0.5)); }, box(0.1, 4)},
    {"pow-const-base", [](auto &c, auto x, auto) { return c.pow(c.constant(2), x); }, box(-2, 2)},
    {"if", [](auto &c, auto x, auto y) {
       return c.ifThenElse(c.compare(CompareKind::Lt, x, y), c.call(FuncKind::Sin, c.mul(x, y)), c.div(x, y)); },
     [](std::mt19937 &rng) { auto p = apart(0.5, 2)(rng); return p; }},
    {"div", [](auto &c, auto x, auto y) { return c.div(c.sub(x, y), c.add(c.mul(x, x), c.one())); }, box(-2, 2)},
    {"chain", [](auto &c, auto x, auto y) {
       return c.call(FuncKind::Exp, c.mul(c.call(FuncKind::Sin, c.mul(x, y)), c.call(FuncKind::Cos, x))); }, box(-1, 1)},
};
// clang-format on

class BuiltinDerivative : public ::testing::TestWithParam<Case> {};

double eval(ExprRef e, double x, double y) {
  EvalEnv env;
  env.variable = [&](VarKey k) { return k.var == 0 ? x : y; };
  auto v = evaluate(e, env);
  EXPECT_TRUE(v) << (v ? "" : v.error());
  return v ? *v : NAN;
}

/// Central difference extrapolated once (Richardson): error O(h^4).
double finiteDifference(const std::function<double(double)> &f, double at) {
  auto central = [&](double h) { return (f(at + h) - f(at - h)) / (2 * h); };
  double h = 1e-3 * std::max(1.0, std::abs(at));
  return (4 * central(h / 2) - central(h)) / 3;
}

TEST_P(BuiltinDerivative, MatchesFiniteDifferences) {
  const Case &tc = GetParam();
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  ExprRef e = tc.build(c, x, y);
  Differentiator d(c);
  ExprRef dx = d.partial(e, {0, 0});
  ExprRef dy = d.partial(e, {1, 0});
  std::mt19937 rng(12345);
  for (int i = 0; i < 20; ++i) {
    auto [px, py] = tc.point(rng);
    double fdx = finiteDifference([&](double v) { return eval(e, v, py); }, px);
    double fdy = finiteDifference([&](double v) { return eval(e, px, v); }, py);
    double sx = eval(dx, px, py), sy = eval(dy, px, py);
    EXPECT_LE(std::abs(sx - fdx), 1e-7 * std::max(std::abs(fdx), 1e-4))
        << tc.name << " d/dx at (" << px << ", " << py << "): " << printLsd(dx);
    EXPECT_LE(std::abs(sy - fdy), 1e-7 * std::max(std::abs(fdy), 1e-4))
        << tc.name << " d/dy at (" << px << ", " << py << "): " << printLsd(dy);
  }
}

INSTANTIATE_TEST_SUITE_P(Builtins, BuiltinDerivative,
                         ::testing::ValuesIn(cases), [](const auto &info) {
                           std::string n = info.param.name;
                           for (char &ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch)))
                               ch = '_';
                           return n;
                         });

TEST(Differentiate, PiecewiseRulesAreSymbolic) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  Differentiator d(c);
  EXPECT_EQ(printLsd(d.partial(c.call(FuncKind::Abs, x), {0, 0})), "sign(v0)");
  EXPECT_EQ(printLsd(d.partial(c.call(FuncKind::Sign, x), {0, 0})), "0");
  EXPECT_EQ(printLsd(d.partial(c.call(FuncKind::Min, x, y), {0, 0})),
            "if v0 < v1 then 1 else 0");
  EXPECT_EQ(printLsd(d.partial(c.call(FuncKind::Max, x, y), {1, 0})),
            "if v0 > v1 then 0 else 1");
  EXPECT_EQ(printLsd(d.partial(c.call(FuncKind::Mod, x, y), {1, 0})),
            "-floor(v0 / v1)");
  EXPECT_EQ(printLsd(d.partial(c.pow(x, c.constant(3)), {0, 0})), "3 * v0^2");
  // A kept log(x)^0 is constant where defined: its derivative is 0.
  ExprRef zeroPower = c.pow(c.call(FuncKind::Log, x), c.zero());
  EXPECT_EQ(d.partial(zeroPower, {0, 0}), c.zero());
  // General power: both terms.
  ExprRef power = c.pow(x, y);
  EXPECT_EQ(d.partial(power, {1, 0}),
            c.mul(power, c.call(FuncKind::Log, x)));
}

TEST(Differentiate, TimeDerivativeMatchesHandComputation) {
  // e = x^2 * sin(y) + exp(time * x) / z + p * pre(x)
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1), z = c.var(2), t = c.time(),
          p = c.param(0);
  ExprRef e =
      c.add(c.add(c.mul(c.pow(x, c.constant(2)), c.call(FuncKind::Sin, y)),
                  c.div(c.call(FuncKind::Exp, c.mul(t, x)), z)),
            c.mul(p, c.pre(0)));
  Differentiator d(c);
  ExprRef de = d.timeDerivative(e);
  EXPECT_FALSE(dependsOn(de, {0, 2}));
  EXPECT_TRUE(dependsOn(de, {0, 1}));
  EXPECT_EQ(freeParameters(de).size(), 0u); // p * pre(x) is constant

  std::mt19937 rng(7);
  for (int i = 0; i < 10; ++i) {
    double v[3], dv[3], tv = uniform(rng, 0, 2);
    for (int k = 0; k < 3; ++k) {
      v[k] = uniform(rng, 0.5, 1.5);
      dv[k] = uniform(rng, -1, 1);
    }
    // 2 x x' sin y + x^2 cos y y' + exp(t x) (x + t x') / z - exp(t x) z' / z^2
    double expected = 2 * v[0] * dv[0] * std::sin(v[1]) +
                      v[0] * v[0] * std::cos(v[1]) * dv[1] +
                      std::exp(tv * v[0]) * (v[0] + tv * dv[0]) / v[2] -
                      std::exp(tv * v[0]) * dv[2] / (v[2] * v[2]);
    EvalEnv env;
    env.time = tv;
    env.variable = [&](VarKey k) {
      return k.order == 0 ? v[k.var] : dv[k.var];
    };
    env.parameter = [](ParamId) { return 3.0; };
    auto got = evaluate(de, env);
    ASSERT_TRUE(got);
    EXPECT_NEAR(*got, expected, 1e-12 * std::abs(expected));
  }
}

TEST(Differentiate, TimeDerivativeIsTheHashConsedHandResult) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  Differentiator d(c);
  // d/dt (x*y + time) = der(x)*y + x*der(y) + 1
  ExprRef e = c.add(c.mul(x, y), c.time());
  ExprRef terms[] = {c.mul(c.var(0, 1), y), c.mul(x, c.var(1, 1)), c.one()};
  EXPECT_EQ(d.timeDerivative(e), c.add(terms));
  // Higher orders: d/dt der(x) = der(der(x)); pre and parameters vanish.
  EXPECT_EQ(d.timeDerivative(c.var(0, 1)), c.var(0, 2));
  EXPECT_EQ(d.timeDerivative(c.mul(c.param(0), c.pre(1))), c.zero());
  // Partial with respect to der(x) treats x as independent.
  ExprRef f = c.mul(c.var(0, 1), x);
  EXPECT_EQ(d.partial(f, {0, 1}), x);
  EXPECT_EQ(d.partial(f, {0, 0}), c.var(0, 1));
}

TEST(Differentiate, SharedDagStaysLinear) {
  // e_{k+1} = sin(e_k) * e_k + x: a DAG of ~4n nodes, a tree of 2^n.
  ExprContext c;
  ExprRef x = c.var(0), e = x;
  const int n = 2000;
  for (int k = 0; k < n; ++k)
    e = c.add(c.mul(c.call(FuncKind::Sin, e), e), x);
  Differentiator d(c);
  ExprRef dt = d.timeDerivative(e);
  ExprRef dx = d.partial(e, {0, 0});
  EXPECT_LT(dagSize(dt), 10 * dagSize(e));
  EXPECT_LT(dagSize(dx), 10 * dagSize(e));
  // The derivative agrees with a finite difference after unrolling.
  double at = 0.3;
  double fd = finiteDifference([&](double v) { return eval(e, v, 0); }, at);
  EXPECT_NEAR(eval(dx, at, 0), fd, 1e-7 * std::abs(fd));
}

} // namespace
