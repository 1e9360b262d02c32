// What the analysis tells a user about a wrong model: structural
// singularity (Dulmage–Mendelsohn, in the user's names and lines),
// conflicting fixed start values, aliases with conflicting fixed values;
// and the alias, pruning and report outputs.
#include "TestModels.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <sstream>

using namespace ldae;
using namespace ldae::passtest;

TEST(Diagnostics, StructurallySingularNamesEquationsAndVariables) {
  Builder b("Bad", "pend.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x"), F = b.var("F");
  (void)F;
  b.eq(x, c.constant(1), "x = 1");               // line 4
  b.eq(c.mul(c.constant(2), x), c.constant(3), "2 * x = 3"); // line 5
  Outcome run = analyze(b);
  EXPECT_FALSE(run.ok);
  ASSERT_EQ(run.diags.size(), 1u);
  // The geometric algorithm speaks first: x = 1 and 2 x = 3 conflict.
  EXPECT_EQ(run.diags[0].message,
            "the model has no solution: the constraint '2 * x - 3 = 0', "
            "derived from the equation at pend.lsd:5, cannot hold");
  ASSERT_TRUE(run.result.sga);
  EXPECT_EQ(run.result.sga->outcome, passes::SgaReport::Outcome::NoSolution);
  // Notes point at the equation and at the one it conflicts with.
  ASSERT_EQ(run.diags[0].notes.size(), 2u);
  EXPECT_EQ(run.diags[0].notes[0].message, "equation '2 * x = 3'");
  EXPECT_EQ(run.diags[0].notes[0].range.begin.line, 5u);
  EXPECT_EQ(run.diags[0].notes[1].message, "equation 'x = 1'");
  EXPECT_EQ(run.diags[0].notes[1].range.begin.line, 4u);
}

TEST(Diagnostics, OnlyUnderDetermined) {
  Builder b("Free", "free.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x"), y = b.var("y");
  b.eq(c.add(x, y), c.constant(1), "x + y = 1");
  Outcome run = analyze(b);
  EXPECT_FALSE(run.ok);
  ASSERT_EQ(run.diags.size(), 1u);
  EXPECT_EQ(run.diags[0].message,
            "the model does not determine its solution: 1 free function(s) "
            "remain (gauge freedom); nothing fixes the evolution of 'x' and "
            "'y'");
}

TEST(Diagnostics, ThreeEquationsOverOneVariable) {
  Builder b("Over", "over.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x"), y = b.var("y"), z = b.var("z");
  b.eq(c.mul(x, x), c.constant(1), "x * x = 1");
  b.eq(c.call(ir::FuncKind::Sin, x), c.constant(0.5), "sin(x) = 0.5");
  b.eq(c.call(ir::FuncKind::Exp, x), c.constant(2), "exp(x) = 2");
  b.eq(c.add(y, z), x, "y + z = x");
  Outcome run = analyze(b);
  EXPECT_FALSE(run.ok);
  ASSERT_GE(run.diags.size(), 1u);
  // x * x = 1 allows x = 1 or -1; sin(x) = 0.5 then cannot hold.
  EXPECT_EQ(run.diags[0].message,
            "the model has no solution: the constraint 'sin(x) - 0.5 = 0', "
            "derived from the equation at over.lsd:6, cannot hold");
}

TEST(Diagnostics, ConflictingFixedStartValuesAreNamed) {
  // x and y both fixed, at a point off the circle: the constraint ties them.
  Builder b("Pendulum", "pend.lsd");
  b.var("x", 1, true);
  b.var("y", 1, true);
  pendulumFirstOrder(b);
  Outcome run = analyze(b);
  EXPECT_FALSE(run.ok);
  ASSERT_EQ(run.diags.size(), 1u) << run.messages;
  EXPECT_EQ(run.diags[0].message,
            "the initial conditions conflict: fixed start values of 'x' and "
            "'y' over-determine the initialization; the model can take 1 of "
            "them; free 'y'");
  EXPECT_EQ(run.result.init.conflicting,
            (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(run.result.init.toFree, (std::vector<std::string>{"y"}));
  EXPECT_FALSE(run.result.init.consistent);
}

TEST(Diagnostics, RedundantButConsistentFixedValuesAreAccepted) {
  Builder b("Pendulum", "pend.lsd");
  b.var("x", 0.6, true);
  b.var("y", -0.8, true);
  pendulumFirstOrder(b, {}, 0.6, -0.8);
  Outcome run = analyze(b);
  EXPECT_TRUE(run.ok) << run.messages;
  ASSERT_EQ(run.diags.size(), 1u) << run.messages;
  EXPECT_EQ(run.diags[0].severity, Severity::Warning);
  EXPECT_EQ(run.diags[0].message,
            "the fixed start values of 'x' and 'y' are redundant but "
            "consistent; the model takes 1 of them, the others ('y') are "
            "start guesses");
  EXPECT_TRUE(run.result.init.consistent);
  // The one the model cannot take is a guess from here on.
  ASSERT_TRUE(run.result.system);
  for (const ir::SystemUnknown &u : run.result.system->unknowns)
    if (u.name == "x" || u.name == "y")
      EXPECT_EQ(u.fixed, u.name == "x") << u.name;
}

TEST(Diagnostics, InitializationDegreesOfFreedom) {
  // Pendulum with x and v fixed: 2 states, 2 conditions, dof 0.
  Builder b("Pendulum", "pend.lsd");
  b.var("x", 0.6, true);
  b.var("y", -0.8);
  b.var("u");
  b.var("v", 0, true);
  pendulumFirstOrder(b, {}, 0.6, -0.8);
  Outcome run = analyze(b);
  EXPECT_TRUE(run.ok) << run.messages;
  const passes::InitReport &init = run.result.init;
  EXPECT_EQ(init.fixed, (std::vector<std::string>{"v", "x"}));
  EXPECT_EQ(init.honoured, init.fixed);
  // Unknowns: 11 slots + 2 state derivatives; equations: 11 + 2 fixed.
  EXPECT_EQ(init.unknowns - init.equations, 0);
  EXPECT_EQ(init.dof, 0);
}

TEST(Diagnostics, AliasesWithConflictingFixedValues) {
  Builder b("Alias", "alias.lsd");
  auto &c = b.ctx();
  ir::ExprRef a = b.var("a", 1, true), bb = b.var("b", 2, true);
  b.eq(b.der(a), c.neg(a), "der(a) = -a");
  b.eq(bb, a, "b = a");
  Outcome run = analyze(b);
  EXPECT_FALSE(run.ok);
  ASSERT_EQ(run.diags.size(), 1u);
  EXPECT_EQ(run.diags[0].message,
            "'b' has fixed start value 2 but its alias 'a' has fixed start "
            "value 1");
}

TEST(Aliases, RemovedAndReportedAsOutputs) {
  Builder b("Alias", "alias.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x", 1), p = b.var("p.v"), n = b.var("n.v"),
              k = b.var("k");
  b.eq(b.der(x), c.neg(x), "der(x) = -x");
  b.eq(p, x, "p.v = x");
  b.eq(n, c.neg(p), "n.v = -p.v");
  b.eq(k, c.constant(3), "k = 3");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  EXPECT_EQ(run.result.aliasesRemoved, 3);
  EXPECT_EQ(run.result.aliases,
            (std::vector<std::string>{"k = 3", "n.v = -x", "p.v = x"}));
  ASSERT_TRUE(run.result.system);
  EXPECT_EQ(run.result.system->unknowns.size(), 1u);
  std::map<std::string, std::string> out;
  for (const ir::SystemOutput &o : run.result.system->outputs)
    out[o.name] = ir::printLsd(o.value, &b.model);
  EXPECT_EQ(out["n.v"], "-x");
  EXPECT_EQ(out["k"], "3");
  EXPECT_EQ(out["der(x)"], "der(x)");
}

TEST(Prune, KeepsOnlyWhatTheOutputsNeed) {
  // Two independent oscillators and an algebraic read-out of the second.
  Builder b("Two", "two.lsd");
  auto &c = b.ctx();
  ir::ExprRef x1 = b.var("x1", 1), v1 = b.var("v1"), x2 = b.var("x2", 1),
              v2 = b.var("v2"), e2 = b.var("e2");
  b.eq(b.der(x1), v1, "der(x1) = v1");
  b.eq(b.der(v1), c.neg(x1), "der(v1) = -x1");
  b.eq(b.der(x2), v2, "der(x2) = v2");
  b.eq(b.der(v2), c.neg(x2), "der(v2) = -x2");
  b.eq(e2, c.mul(v2, v2), "e2 = v2 * v2");
  passes::PipelineOptions opts = indexOneOptions();
  opts.outputs = {"x1"};
  Outcome run = analyze(b, opts);
  ASSERT_TRUE(run.ok) << run.messages;
  ASSERT_TRUE(run.result.system);
  std::vector<std::string> names;
  for (const auto &u : run.result.system->unknowns)
    names.push_back(u.name);
  EXPECT_EQ(names, (std::vector<std::string>{"v1", "x1"}));
  EXPECT_EQ(run.result.prunedUnknowns, 3);
  EXPECT_EQ(run.result.system->stateSets[0].residuals.size(), 2u);
  ASSERT_EQ(run.result.system->outputs.size(), 1u);
  EXPECT_EQ(run.result.system->outputs[0].name, "x1");

  Builder b2("Two", "two.lsd");
  b2.var("x");
  b2.eq(b2.der(b2.var("x")), b2.ctx().constant(1), "der(x) = 1");
  passes::PipelineOptions bad = indexOneOptions();
  bad.outputs = {"nope"};
  Outcome r2 = analyze(b2, bad);
  EXPECT_FALSE(r2.ok);
  EXPECT_EQ(r2.messages, "unknown output 'nope'\n");
}

TEST(Report, JsonAndTextAndReducedModel) {
  Builder b("Pendulum", "pend.lsd");
  pendulumFirstOrder(b);
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok);
  nlohmann::json j = passes::analysisToJson(run.result);
  EXPECT_EQ(j["model"], "Pendulum");
  EXPECT_EQ(j["variables"], 5);
  EXPECT_EQ(j["equations"], 5);
  EXPECT_EQ(j["aliases_removed"], 0);
  EXPECT_EQ(j["structural_index"], 3);
  EXPECT_EQ(j["differentiation_index"], 3);
  EXPECT_EQ(j["dof"], 2);
  EXPECT_EQ(j["states"], (std::vector<std::string>{"v", "y"}));
  ASSERT_EQ(j["differentiated"].size(), 3u);
  EXPECT_EQ(j["differentiated"][2]["equation"], "x^2 + y^2 = L^2");
  EXPECT_EQ(j["differentiated"][2]["location"], "pend.lsd:13");
  EXPECT_EQ(j["differentiated"][2]["times"], 2);
  EXPECT_TRUE(j["blt"].is_array());
  EXPECT_EQ(j["init"]["dof"], 2);
  EXPECT_EQ(j["state_sets"].size(), 2u);
  EXPECT_EQ(j["outcome"], "unique");
  EXPECT_EQ(j["free_functions"], 0);
  EXPECT_EQ(j["constraints"].size(), 3u); // position, velocity, lambda

  std::ostringstream text;
  passes::printAnalysis(run.result, text);
  EXPECT_NE(text.str().find("structural index:     3"), std::string::npos);
  EXPECT_NE(text.str().find("2x  x^2 + y^2 = L^2  (pend.lsd:13)"),
            std::string::npos);

  std::string reduced = passes::printReduced(*run.result.system);
  EXPECT_NE(reduced.find("model Pendulum_reduced"), std::string::npos);
  // der(der(x)) is a dummy in both sets; der(x) only in the first, so it
  // is a variable of its own tied to der(y)'s role by a link equation.
  EXPECT_NE(reduced.find("Real der_der_x(start = 0) \"der(der(x)) (dummy "
                         "derivative)\";"),
            std::string::npos)
      << reduced;
  EXPECT_NE(reduced.find("0 = der(y) - der_y;"), std::string::npos)
      << reduced;
  EXPECT_NE(reduced.find("0 = der_x - u;"), std::string::npos) << reduced;
  EXPECT_NE(reduced.find("end Pendulum_reduced;"), std::string::npos);
}
