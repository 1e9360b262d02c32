// Model: name lookup, the user's spelling of derivatives, and print() as
// complete lsd source with quoted flat names and non-default attributes.
#include "ir/Model.h"

#include <gtest/gtest.h>

using namespace ldae::ir;

namespace {

TEST(Model, NamesAndLookup) {
  Model m;
  Variable x;
  x.name = "x";
  Variable v;
  v.name = "r1.v";
  EXPECT_EQ(m.addVariable(x), 0u);
  EXPECT_EQ(m.addVariable(v), 1u);
  Parameter p;
  p.name = "g";
  p.value = 9.81;
  EXPECT_EQ(m.addParameter(p), 0u);
  EXPECT_EQ(m.findVariable("r1.v"), 1u);
  EXPECT_FALSE(m.findVariable("y"));
  EXPECT_EQ(m.findParameter("g"), 0u);
  EXPECT_FALSE(m.findParameter("x"));
  EXPECT_EQ(m.parameterValues(), std::vector<double>{9.81});
  EXPECT_EQ(m.variableName(VarKey{0, 0}), "x");
  EXPECT_EQ(m.variableName(VarKey{1, 1}), "der(r1.v)");
  EXPECT_EQ(m.variableName(VarKey{0, 2}), "der(der(x))");
  EXPECT_EQ(m.parameterName(0), "g");
  EXPECT_STREQ(stateSelectName(StateSelect::Prefer), "prefer");
  EXPECT_STREQ(stateSelectName(StateSelect::Never), "never");
}

TEST(Model, PrintsFlatLsd) {
  Model m;
  m.name = "Pendulum";
  ExprContext &c = m.ctx();
  Parameter L{.name = "L", .value = 1.5};
  Parameter n{.name = "n", .value = 3, .isInteger = true};
  Parameter on{.name = "on", .value = 1, .isConstant = true, .isBoolean = true};
  ParamId pL = m.addParameter(L);
  m.addParameter(n);
  m.addParameter(on);
  Variable x{.name = "x", .start = 1, .hasStart = true, .fixed = true};
  Variable y{.name = "y"};
  Variable v{.name = "r1.v",
             .nominal = 1e-3,
             .min = 0,
             .max = 10,
             .stateSelect = StateSelect::Prefer,
             .unit = "V"};
  Variable b{.name = "b", .isDiscrete = true, .isBoolean = true};
  VarId ix = m.addVariable(x), iy = m.addVariable(y), iv = m.addVariable(v);
  VarId ib = m.addVariable(b);
  ExprRef X = c.var(ix), Y = c.var(iy), V = c.var(iv);
  auto eq = [&](ExprRef r) { return Equation{.residual = r}; };
  m.equations.push_back(eq(c.sub(c.var(ix, 1), V)));
  ExprRef t[] = {c.pow(X, c.constant(2)), c.pow(Y, c.constant(2)),
                 c.neg(c.pow(c.param(pL), c.constant(2)))};
  m.equations.push_back(eq(c.add(t)));
  ExprRef vdd = c.var(iv, 2);
  m.equations.push_back(eq(c.add(vdd, c.mul(c.constant(4), V))));
  m.equations.push_back(eq(c.sub(c.neg(Y), c.call(FuncKind::Sin, c.time()))));
  m.equations.push_back(
      eq(c.sub(c.var(ib), c.compare(CompareKind::Gt, Y, c.zero()))));
  m.initialEquations.push_back(eq(c.var(ix, 1)));
  WhenClause w;
  w.condition = c.compare(CompareKind::Lt, X, c.zero());
  w.reinits.push_back({iv, c.mul(c.constant(-0.8), c.pre(iv)), {}});
  m.whenClauses.push_back(w);
  m.experiment.stopTime = 10;
  m.experiment.tolerance = 1e-6;
  EXPECT_EQ(m.print(), R"(model Pendulum
  parameter Real L = 1.5;
  parameter Integer n = 3;
  constant Boolean on = true;
  Real x(start = 1, fixed = true);
  Real y;
  Real 'r1.v'(nominal = 0.001, min = 0, max = 10, unit = "V", stateSelect = StateSelect.prefer);
  Boolean b;
equation
  der(x) = 'r1.v';
  x^2 + y^2 = L^2;
  4 * 'r1.v' + der(der('r1.v')) = 0;
  0 = y + sin(time);
  b = y > 0;
  when x < 0 then
    reinit('r1.v', -0.8 * pre('r1.v'));
  end when;
initial equation
  der(x) = 0;
  annotation(experiment(StopTime = 10, Tolerance = 1e-06));
end Pendulum;
)");
}

TEST(Model, EquationSidesRebuildTheResidual) {
  ExprContext c;
  ExprRef x = c.var(0), y = c.var(1);
  // lhs - rhs of the printed equation is the residual again.
  EXPECT_EQ(printEquation(c, c.sub(x, c.constant(2))), "v0 = 2");
  EXPECT_EQ(printEquation(c, c.add(x, c.constant(2))), "v0 = -2");
  EXPECT_EQ(printEquation(c, c.sub(c.mul(x, y), c.mul(c.constant(3), y))),
            "v0 * v1 = 3 * v1");
  EXPECT_EQ(printEquation(c, c.call(FuncKind::Sin, x)), "sin(v0) = 0");
  EXPECT_EQ(printEquation(c, c.neg(c.call(FuncKind::Sin, x))), "0 = sin(v0)");
}

} // namespace
