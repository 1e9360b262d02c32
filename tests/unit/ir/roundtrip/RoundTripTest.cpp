// Model::print must be lsd the frontend reads back to the same model: a
// model with a varied set of expressions (every operator, precedence case,
// quoted flat name, derivative order, attribute) is printed, compiled again
// from the text, and compared equation by equation at random points and as
// printed text (printing is a fixpoint).
#include "frontend/Frontend.h"
#include "ir/Evaluate.h"
#include "ir/Model.h"

#include <gtest/gtest.h>
#include <random>

using namespace ldae;
using namespace ldae::ir;

namespace {

std::unique_ptr<Model> variedModel() {
  auto m = std::make_unique<Model>();
  m->name = "RoundTrip";
  ExprContext &c = m->ctx();
  ParamId pL = m->addParameter({.name = "L", .value = 1.5});
  ParamId pk = m->addParameter({.name = "k", .value = 0.1});
  const char *names[] = {"x", "y", "z", "r1.v", "m[2].s", "w"};
  std::vector<ExprRef> v;
  for (const char *n : names) {
    Variable var{.name = n};
    if (std::string(n) == "x") {
      var.start = 1;
      var.hasStart = true;
      var.fixed = true;
    }
    if (std::string(n) == "r1.v") {
      var.nominal = 1e-3;
      var.min = -10;
      var.stateSelect = StateSelect::Prefer;
    }
    v.push_back(c.var(m->addVariable(var)));
  }
  ExprRef x = v[0], y = v[1], z = v[2], rv = v[3], ms = v[4], w = v[5];
  ExprRef L = c.param(pL), k = c.param(pk);
  auto num = [&](double d) { return c.constant(d); };
  auto eq = [&](ExprRef r) { m->equations.push_back({.residual = r}); };
  ExprRef terms[] = {c.pow(x, num(2)), c.pow(y, num(2)),
                     c.neg(c.pow(L, num(2)))};
  eq(c.add(terms));
  eq(c.sub(c.var(0, 1), c.mul(k, c.div(rv, c.add(y, num(2))))));
  eq(c.sub(c.var(1, 2), c.mul(c.neg(x), c.call(FuncKind::Sin, c.time()))));
  eq(c.sub(rv, c.pow(c.mul(x, y), num(3))));
  eq(c.sub(z, c.div(c.neg(x), c.mul(num(2), c.call(FuncKind::Exp, y)))));
  eq(c.sub(ms, c.pow(num(2), c.neg(z))));
  eq(c.sub(w,
           c.ifThenElse(c.compare(CompareKind::Lt, x, y),
                        c.ifThenElse(c.compare(CompareKind::Ge, z, num(0)),
                                     c.call(FuncKind::Atan2, y, x),
                                     c.call(FuncKind::Min, x, z)),
                        c.mul(num(0.1), c.call(FuncKind::Mod, rv, num(3))))));
  eq(c.add(c.var(3, 1), c.mul(k, c.call(FuncKind::Abs, c.sub(rv, c.pre(3))))));
  m->initialEquations.push_back({.residual = c.sub(c.var(3, 1), num(1e-300))});
  m->experiment.stopTime = 2.5;
  return m;
}

TEST(RoundTrip, PrintedModelReadsBackToTheSameModel) {
  std::unique_ptr<Model> original = variedModel();
  std::string text = original->print();
  SourceManager sources;
  DiagnosticEngine diags(sources);
  std::unique_ptr<Model> back = frontend::compileSource(
      "roundtrip.lsd", text, frontend::FrontendOptions{}, sources, diags);
  ASSERT_TRUE(back) << text;
  EXPECT_EQ(back->print(), text);
  ASSERT_EQ(back->variables.size(), original->variables.size());
  ASSERT_EQ(back->equations.size(), original->equations.size());

  // Same residuals at random points, variables matched by name.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.2, 2);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> values(original->variables.size() * 3);
    for (double &d : values)
      d = u(rng);
    auto envFor = [&](const Model &m) {
      EvalEnv env;
      env.time = 0.7;
      env.variable = [&, mp = &m](VarKey key) {
        auto id = *original->findVariable(mp->variables[key.var].name);
        return values[id * 3 + key.order];
      };
      env.parameter = [mp = &m](ParamId p) { return mp->parameters[p].value; };
      return env;
    };
    EvalEnv e1 = envFor(*original), e2 = envFor(*back);
    for (size_t i = 0; i < original->equations.size(); ++i) {
      auto a = evaluate(original->equations[i].residual, e1, original.get());
      auto b = evaluate(back->equations[i].residual, e2, back.get());
      ASSERT_TRUE(a && b);
      EXPECT_NEAR(*a, *b, 1e-12 * (1 + std::abs(*a))) << "equation " << i;
    }
  }
}

} // namespace
