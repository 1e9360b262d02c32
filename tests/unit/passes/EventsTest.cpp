// The "events" pass (docs/events.md): the discrete layout, and the event
// update, roots, reinits and time events evaluated with ir::evaluate at
// given points, on the bouncing ball, a hysteresis controller, the
// Modelica IdealDiode form, a sampled controller and an ideal switch.
#include "frontend/Frontend.h"
#include "ir/Evaluate.h"
#include "passes/Pipeline.h"

#include <gtest/gtest.h>

#include <map>

using namespace ldae;

namespace {

struct Compiled {
  std::unique_ptr<ir::Model> model;
  passes::AnalysisResult result;
  std::string messages;
  bool ok = false;
  const ir::DaeSystem &sys() const { return *result.system; }
};

Compiled compile(const std::string &text,
                 const passes::PipelineOptions &opts = {}) {
  Compiled c;
  SourceManager sources;
  DiagnosticEngine diags(sources);
  c.model = frontend::compileSource("test.lsd", text, {}, sources, diags);
  if (c.model)
    c.ok = passes::runPipeline(*c.model, opts, diags, c.result) &&
           c.result.system;
  for (const Diagnostic &d : diags.diagnostics())
    c.messages += diags.render(d);
  return c;
}

/// A point of (t, y, parameters, discrete state) by name.
struct Point {
  double time = 0;
  std::map<std::string, double> y;   // unknowns by name
  std::map<std::string, double> cur; // discrete values by name
  std::map<std::string, double> pre; // their pre() values
};

double eval(const ir::DaeSystem &sys, ir::ExprRef e, const Point &pt) {
  const size_t user = sys.parameterValues.size();
  const size_t nd = sys.events.discrete.size();
  ir::EvalEnv env;
  env.time = pt.time;
  env.variable = [&](ir::VarKey k) {
    for (const ir::SystemUnknown &u : sys.unknowns)
      if (u.key == k) {
        auto it = pt.y.find(u.name);
        return it == pt.y.end() ? 0.0 : it->second;
      }
    ADD_FAILURE() << "reads a variable that is no unknown";
    return 0.0;
  };
  env.parameter = [&](ir::ParamId p) {
    if (p < user)
      return sys.parameterValues[p];
    size_t k = (p - user) % nd;
    const std::map<std::string, double> &m = p - user < nd ? pt.cur : pt.pre;
    auto it = m.find(sys.events.discrete[k].name);
    return it == m.end() ? sys.events.discrete[k].start : it->second;
  };
  Expected<double> v = ir::evaluate(e, env);
  EXPECT_TRUE(v) << v.error();
  return v ? *v : 0.0;
}

int discreteIndex(const ir::DaeSystem &sys, const std::string &name) {
  for (size_t k = 0; k < sys.events.discrete.size(); ++k)
    if (sys.events.discrete[k].name == name)
      return static_cast<int>(k);
  ADD_FAILURE() << "no discrete value " << name;
  return 0;
}

int unknownIndex(const ir::DaeSystem &sys, const std::string &name) {
  for (size_t i = 0; i < sys.unknowns.size(); ++i)
    if (sys.unknowns[i].name == name)
      return static_cast<int>(i);
  ADD_FAILURE() << "no unknown " << name;
  return 0;
}

double update(const Compiled &c, const std::string &name, const Point &pt) {
  return eval(c.sys(), c.sys().events.update[discreteIndex(c.sys(), name)],
              pt);
}

} // namespace

TEST(Events, BouncingBall) {
  Compiled c = compile(R"(
model Ball
  parameter Real e = 0.8;
  Real h(start = 1, fixed = true);
  Real v(start = 0, fixed = true);
equation
  der(h) = v;
  der(v) = -9.81;
  when h <= 0 then
    reinit(v, -e * pre(v));
  end when;
end Ball;)");
  ASSERT_TRUE(c.ok) << c.messages;
  const ir::DaeSystem &sys = c.sys();
  const ir::EventSystem &ev = sys.events;
  // The user's parameter only; the discrete state after it.
  EXPECT_EQ(sys.parameterNames, std::vector<std::string>{"e"});
  ASSERT_EQ(ev.discrete.size(), 3u);
  EXPECT_EQ(ev.discrete[0].name, "initial()");
  EXPECT_EQ(ev.discrete[0].kind, ir::DiscreteKind::Initial);
  EXPECT_EQ(ev.discrete[1].name, "h <= 0");
  EXPECT_EQ(ev.discrete[1].kind, ir::DiscreteKind::Relation);
  EXPECT_EQ(ev.discrete[2].kind, ir::DiscreteKind::When);
  EXPECT_EQ(ev.discrete[1].start, 0); // h = 1 at the start
  ASSERT_EQ(sys.roots.size(), 1u);
  EXPECT_EQ(ev.rootRelation, std::vector<uint32_t>{1});
  EXPECT_EQ(eval(sys, sys.roots[0], {.y = {{"h", 0.25}}}), 0.25);
  ASSERT_EQ(ev.update.size(), 3u);
  EXPECT_EQ(update(c, "h <= 0", {.y = {{"h", -1e-12}}}), 1);
  EXPECT_EQ(update(c, "h <= 0", {.y = {{"h", 1e-12}}}), 0);
  // reinit(v, -e * pre(v)): pre(v) is v just before the event.
  ASSERT_EQ(ev.reinits.size(), 1u);
  EXPECT_EQ(ev.reinits[0].unknown, static_cast<uint32_t>(unknownIndex(sys, "v")));
  Point hit{.y = {{"h", -1e-12}, {"v", -4.0}}};
  EXPECT_DOUBLE_EQ(eval(sys, ev.reinits[0].value, hit), 3.2);
  EXPECT_EQ(eval(sys, ev.reinits[0].fired, hit), 1);
  // Not again while the condition stays true, nor at the initial event.
  hit.pre["when h <= 0"] = 1;
  EXPECT_EQ(eval(sys, ev.reinits[0].fired, hit), 0);
  hit.pre["when h <= 0"] = 0;
  hit.cur["initial()"] = 1;
  EXPECT_EQ(eval(sys, ev.reinits[0].fired, hit), 0);
  EXPECT_TRUE(ev.modeDiscrete.empty());
}

TEST(Events, HysteresisController) {
  Compiled c = compile(R"(
model Hysteresis
  parameter Real Tlow = 19, Thigh = 21;
  Real T(start = 20, fixed = true);
  Boolean heat(start = true);
equation
  der(T) = if heat then 1 else -1;
  when T > Thigh then
    heat = false;
  elsewhen T < Tlow then
    heat = true;
  end when;
end Hysteresis;)");
  ASSERT_TRUE(c.ok) << c.messages;
  const ir::DaeSystem &sys = c.sys();
  EXPECT_EQ(sys.events.discrete[discreteIndex(sys, "heat")].start, 1);
  EXPECT_EQ(sys.roots.size(), 2u);
  // The continuous equation reads heat's frozen value: heat = 0 gives -1.
  const ir::ExprRef res = sys.stateSets[0].residuals[0];
  ir::EvalEnv env;
  env.variable = [](ir::VarKey) { return 0.0; };
  env.parameter = [&](ir::ParamId p) {
    return p < 2 ? sys.parameterValues[p] : 0.0;
  };
  Expected<double> r = ir::evaluate(res, env);
  ASSERT_TRUE(r);
  EXPECT_EQ(std::abs(*r), 1.0);
  // Above Thigh: off; below Tlow: on; between: keeps pre(heat).
  EXPECT_EQ(update(c, "heat", {.y = {{"T", 21.5}}, .pre = {{"heat", 1}}}), 0);
  EXPECT_EQ(update(c, "heat", {.y = {{"T", 18.5}}, .pre = {{"heat", 0}}}), 1);
  EXPECT_EQ(update(c, "heat", {.y = {{"T", 20}}, .pre = {{"heat", 0}}}), 0);
  EXPECT_EQ(update(c, "heat", {.y = {{"T", 20}}, .pre = {{"heat", 1}}}), 1);
  // Above Thigh with its when already true: no new edge, heat stays.
  EXPECT_EQ(update(c, "heat",
                   {.y = {{"T", 21.5}},
                    .pre = {{"heat", 1}, {"when T > Thigh", 1}}}),
            1);
}

TEST(Events, IdealDiode) {
  Compiled c = compile(R"(
model Rectifier
  parameter Real Ron = 1e-5, Goff = 1e-5, R = 10, C = 1e-3;
  Real s(start = 0);
  Real vd, i, vc(start = 0, fixed = true);
  Boolean off;
equation
  off = s < 0;
  vd = s * (if off then 1 else Ron);
  i = s * (if off then Goff else 1);
  sin(100 * time) - vd = vc;
  C * der(vc) = i - vc / R;
end Rectifier;)");
  ASSERT_TRUE(c.ok) << c.messages;
  const ir::DaeSystem &sys = c.sys();
  ASSERT_EQ(sys.events.discrete.size(), 2u);
  EXPECT_EQ(sys.events.discrete[0].name, "off");
  EXPECT_EQ(sys.events.discrete[1].name, "s < 0");
  EXPECT_EQ(c.result.equations, 4); // off = s < 0 is discrete
  EXPECT_EQ(c.result.variables, 4);
  // Same incidence in both branches: one structure, off frozen.
  EXPECT_TRUE(sys.events.modeDiscrete.empty());
  ASSERT_EQ(sys.roots.size(), 1u);
  // s is computed, (sin(100 t) - vc) / (if off then 1 else Ron): its sign
  // is that of -vc at t = 0, in either branch.
  EXPECT_EQ(unknownIndex(sys, "vc"), 0);
  EXPECT_EQ(sys.unknowns.size(), 1u);
  EXPECT_EQ(update(c, "off", {.y = {{"vc", 0.5}}}), 1);
  EXPECT_EQ(update(c, "off", {.y = {{"vc", -0.5}}}), 0);
  EXPECT_EQ(update(c, "off", {.y = {{"vc", 0.5}}, .cur = {{"off", 1}}}), 1);
  EXPECT_EQ(update(c, "off", {.y = {{"vc", -0.5}}, .cur = {{"off", 1}}}), 0);
}

TEST(Events, SampledController) {
  Compiled c = compile(R"(
model Sampled
  parameter Real Ts = 0.1;
  Real x(start = 1, fixed = true);
  discrete Real u(start = 0);
  Boolean on;
equation
  der(x) = -x + u;
  on = time > 0.5;
  when sample(0, Ts) then
    u = if on then 1 - pre(x) else -x;
  end when;
end Sampled;)");
  ASSERT_TRUE(c.ok) << c.messages;
  const ir::DaeSystem &sys = c.sys();
  const ir::EventSystem &ev = sys.events;
  ASSERT_EQ(ev.samples.size(), 1u);
  EXPECT_EQ(ev.discrete[ev.sampleDiscrete[0]].kind, ir::DiscreteKind::Sample);
  EXPECT_EQ(eval(sys, ev.samples[0].first, {}), 0);
  EXPECT_EQ(eval(sys, ev.samples[0].second, {}), 0.1);
  // time > 0.5 is a time event at 0.5, 1 at its right limit.
  ASSERT_EQ(ev.timeThresholds.size(), 1u);
  EXPECT_EQ(eval(sys, ev.timeThresholds[0], {}), 0.5);
  EXPECT_TRUE(sys.roots.empty());
  EXPECT_EQ(update(c, "on", {.time = 0.5}), 1);
  EXPECT_EQ(update(c, "on", {.time = 0.4}), 0);
  Point tick{.time = 0.7, .y = {{"x", 0.25}}, .cur = {{"sample(0, Ts)", 1}}};
  EXPECT_EQ(update(c, "u", tick), 0.75);
  tick.time = 0.2;
  EXPECT_EQ(update(c, "u", tick), -0.25);
  tick.cur["sample(0, Ts)"] = 0;
  tick.pre["u"] = 0.5;
  EXPECT_EQ(update(c, "u", tick), 0.5);
}

TEST(Events, IdealSwitchModes) {
  const char *text = R"(
model TwoCaps
  parameter Real C1 = 1, C2 = 2;
  Real v1(start = 10), v2(start = 1), i;
  Boolean closed = time >= 1;
equation
  C1 * der(v1) = -i;
  C2 * der(v2) = i;
  if closed then
    v1 = v2;
  else
    i = 0;
  end if;
end TwoCaps;)";
  Compiled open = compile(text);
  ASSERT_TRUE(open.ok) << open.messages;
  const ir::EventSystem &ev = open.sys().events;
  ASSERT_EQ(ev.modeDiscrete.size(), 1u);
  EXPECT_EQ(ev.discrete[ev.modeDiscrete[0]].name, "closed");
  EXPECT_EQ(ev.modeValues, std::vector<double>{0});
  EXPECT_EQ(open.result.dof, 2);
  passes::PipelineOptions opts;
  opts.modeValues = {1};
  Compiled closed = compile(text, opts);
  ASSERT_TRUE(closed.ok) << closed.messages;
  EXPECT_EQ(closed.sys().events.modeValues, std::vector<double>{1});
  EXPECT_EQ(closed.result.dof, 1); // v1 = v2 ties the capacitors
}

TEST(Events, WhenReadsItsTarget) {
  Compiled c = compile(R"(
model Clock
  Real x(start = 0, fixed = true);
  discrete Real tnext(start = 0.25);
  Integer ticks(start = 0);
equation
  der(x) = 1;
  when time >= tnext then
    tnext = pre(tnext) + 0.25;
    ticks = pre(ticks) + 1;
  end when;
end Clock;)");
  ASSERT_TRUE(c.ok) << c.messages;
  const ir::DaeSystem &sys = c.sys();
  ASSERT_EQ(sys.events.timeThresholds.size(), 1u);
  EXPECT_EQ(eval(sys, sys.events.timeThresholds[0], {.cur = {{"tnext", 0.5}}}),
            0.5);
  // At t = 0.5 with tnext = 0.5: the branch fires, tnext moves on; the
  // relation reads the new tnext, the when-condition the current one.
  Point at{.time = 0.5,
           .cur = {{"tnext", 0.5}},
           .pre = {{"tnext", 0.5}, {"ticks", 1}}};
  EXPECT_EQ(update(c, "tnext", at), 0.75);
  EXPECT_EQ(update(c, "ticks", at), 2);
  EXPECT_EQ(update(c, "time >= tnext", at), 0);
  EXPECT_EQ(update(c, "when time >= tnext", at), 1);
  // The next iteration: its pre() is 1, nothing fires again.
  at.cur["tnext"] = at.pre["tnext"] = 0.75;
  at.pre["when time >= tnext"] = 1;
  at.pre["ticks"] = 2;
  EXPECT_EQ(update(c, "tnext", at), 0.75);
  EXPECT_EQ(update(c, "ticks", at), 2);
}

TEST(Events, Diagnostics) {
  Compiled cycle = compile(R"(
model Cycle
  Real x(start = 1, fixed = true);
  Boolean a, b;
equation
  der(x) = -x;
  a = not b;
  b = a or x > 2;
end Cycle;)");
  EXPECT_FALSE(cycle.ok);
  EXPECT_NE(cycle.messages.find("the discrete equations form a cycle"),
            std::string::npos)
      << cycle.messages;
  Compiled reinit = compile(R"(
model NotState
  Real x(start = 1, fixed = true), y;
equation
  der(x) = -x;
  y = 2 * x;
  when x < 0.5 then
    reinit(y, 1);
  end when;
end NotState;)");
  EXPECT_FALSE(reinit.ok);
  EXPECT_NE(reinit.messages.find(
                "'reinit' of 'y': it is not a state of the reduced system"),
            std::string::npos)
      << reinit.messages;
}
