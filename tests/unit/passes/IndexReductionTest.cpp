// Pantelides and dummy derivatives on the classic examples: the Cartesian
// pendulum (first- and second-order form, and built from components), the
// Mattsson–Söderlind example of seed 004 (eq. 22) and an RLC circuit with a
// capacitor–voltage-source loop.
#include "TestModels.h"

#include "ir/Evaluate.h"

#include <gtest/gtest.h>

#include <functional>
#include <iostream>

using namespace ldae;
using namespace ldae::passtest;
using passes::AnalysisResult;

namespace {
int timesOf(const AnalysisResult &r, const std::string &text) {
  for (const auto &d : r.differentiated)
    if (d.equation == text)
      return d.times;
  return 0;
}
} // namespace

TEST(IndexReduction, PendulumFirstOrder) {
  Builder b("Pendulum", "pend.lsd");
  pendulumFirstOrder(b);
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.structuralIndex, 3);
  EXPECT_EQ(r.differentiationIndex, 3);
  EXPECT_EQ(timesOf(r, "x^2 + y^2 = L^2"), 2);
  EXPECT_EQ(timesOf(r, "der(x) = u"), 1);
  EXPECT_EQ(timesOf(r, "der(y) = v"), 1);
  EXPECT_EQ(r.differentiated.size(), 3u);
  EXPECT_EQ(r.dof, 2);
  // Start at x = 1, y = 0: the constraint's gradient (2x, 2y) pivots on x,
  // so der(x) is a dummy and y, v are the states.
  EXPECT_EQ(r.states, (std::vector<std::string>{"v", "y"}));
  EXPECT_EQ(r.dummies, (std::vector<std::string>{"der(u)", "der(x)",
                                                 "der(der(x))",
                                                 "der(der(y))"}));
  // Two candidate sets: x or y as the state of the position constraint.
  ASSERT_EQ(r.stateSets.size(), 2u);
  EXPECT_EQ(r.stateSets[1].states, (std::vector<std::string>{"u", "x"}));
  ASSERT_TRUE(r.system);
  const ir::DaeSystem &sys = *r.system;
  EXPECT_EQ(sys.stateSets.size(), 2u);
  EXPECT_EQ(sys.unknowns.size(), 9u + 2u); // both sets' dummies have slots
  for (const ir::StateSet &st : sys.stateSets)
    EXPECT_EQ(st.residuals.size(), sys.unknowns.size());
  EXPECT_EQ(sys.stateSets[0].pivotSize, 1u);
  EXPECT_EQ(r.stateSets[0].pivot, (std::vector<std::string>{"2 * x"}));
  EXPECT_EQ(r.stateSets[1].pivot, (std::vector<std::string>{"2 * y"}));
  // The constraint index reduction differentiated is kept for drift.
  ASSERT_EQ(sys.constraints.size(), 3u);
  EXPECT_FALSE(r.bltBlocks.empty());
}

TEST(IndexReduction, PendulumStartingBelowPicksTheOtherSet) {
  Builder b("Pendulum", "pend.lsd");
  pendulumFirstOrder(b, {}, 0, -1);
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  EXPECT_EQ(run.result.states, (std::vector<std::string>{"u", "x"}));
  ASSERT_EQ(run.result.stateSets.size(), 2u);
  EXPECT_EQ(run.result.stateSets[1].states,
            (std::vector<std::string>{"v", "y"}));
}

TEST(IndexReduction, PendulumSecondOrderForm) {
  Builder b("Pendulum2", "pend2.lsd");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x", 1), y = b.var("y"), lam = b.var("lam");
  ir::ExprRef L = b.param("L", 1), g = b.param("g", 9.81);
  b.eq(b.der(x, 2), c.neg(c.mul(lam, x)), "der(der(x)) = -lam * x");
  b.eq(b.der(y, 2), c.sub(c.neg(c.mul(lam, y)), g),
       "der(der(y)) = -lam * y - g");
  b.eq(c.add(c.pow(x, c.constant(2)), c.pow(y, c.constant(2))),
       c.pow(L, c.constant(2)), "x^2 + y^2 = L^2");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.structuralIndex, 3);
  EXPECT_EQ(timesOf(r, "x^2 + y^2 = L^2"), 2);
  EXPECT_EQ(r.differentiated.size(), 1u);
  EXPECT_EQ(r.dof, 2);
  // y and der(y) are the states: the system handed to IDA is first order,
  // with der(y) a first-order unknown of its own.
  EXPECT_EQ(r.states, (std::vector<std::string>{"y", "der(y)"}));
  EXPECT_EQ(r.dummies,
            (std::vector<std::string>{"der(x)", "der(der(x))"}));
  ASSERT_EQ(r.stateSets.size(), 2u);
  EXPECT_EQ(r.stateSets[1].states,
            (std::vector<std::string>{"x", "der(x)"}));
  ASSERT_TRUE(r.system);
  for (const ir::StateSet &st : r.system->stateSets)
    EXPECT_EQ(st.residuals.size(), r.system->unknowns.size());
}

TEST(IndexReduction, PendulumFromComponentsMatches) {
  // A body (position, velocity, force) and a rod (its own copies of the
  // end point, joined to the body by connection equations).
  Builder b("World", "world.lsd");
  auto &c = b.ctx();
  ir::ExprRef bx = b.var("body.x", 1), by = b.var("body.y"),
              bvx = b.var("body.vx"), bvy = b.var("body.vy"),
              bfx = b.var("body.fx"), bfy = b.var("body.fy");
  ir::ExprRef rx = b.var("rod.x"), ry = b.var("rod.y"), rf = b.var("rod.f"),
              rfx = b.var("rod.fx"), rfy = b.var("rod.fy");
  ir::ExprRef m = b.param("body.m", 1), L = b.param("rod.L", 1),
              g = b.param("g", 9.81);
  b.eq(b.der(bx), bvx, "der(x) = vx");
  b.eq(b.der(by), bvy, "der(y) = vy");
  b.eq(c.mul(m, b.der(bvx)), bfx, "m * der(vx) = fx");
  b.eq(c.mul(m, b.der(bvy)), c.sub(bfy, c.mul(m, g)), "m * der(vy) = fy - m * g");
  b.eq(c.add(c.pow(rx, c.constant(2)), c.pow(ry, c.constant(2))),
       c.pow(L, c.constant(2)), "x^2 + y^2 = L^2");
  b.eq(rfx, c.neg(c.mul(rf, rx)), "fx = -f * x");
  b.eq(rfy, c.neg(c.mul(rf, ry)), "fy = -f * y");
  b.eq(rx, bx, "connect(rod.p, body.p)", ir::EquationOrigin::Connection);
  b.eq(ry, by, "connect(rod.p, body.p)", ir::EquationOrigin::Connection);
  b.eq(c.add(rfx, c.neg(bfx)), c.zero(), "connect(rod.p, body.p)",
       ir::EquationOrigin::FlowSum);
  b.eq(c.add(rfy, c.neg(bfy)), c.zero(), "connect(rod.p, body.p)",
       ir::EquationOrigin::FlowSum);
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.aliasesRemoved, 4);
  EXPECT_EQ(r.structuralIndex, 3);
  EXPECT_EQ(timesOf(r, "x^2 + y^2 = L^2"), 2);
  EXPECT_EQ(r.dof, 2);
  EXPECT_EQ(r.states, (std::vector<std::string>{"body.vy", "body.y"}));
  EXPECT_EQ(r.stateSets.size(), 2u);
  // The aliases are outputs of the system.
  ASSERT_TRUE(r.system);
  bool haveRodX = false;
  for (const ir::SystemOutput &o : r.system->outputs)
    haveRodX = haveRodX || (o.name == "rod.x" && o.value == bx);
  EXPECT_TRUE(haveRodX);
}

TEST(IndexReduction, MattssonSoderlindExample) {
  // Seed 004, eq. (22), with the inputs given functions of time:
  // y1 + y2 = u1, y1 + y2 + y3 = u2, y1 + y3' + y4 = u3,
  // 2 y1'' + y2'' + y3'' + y4' = u4.
  Builder b("MattssonSoderlind", "ms.lsd");
  auto &c = b.ctx();
  ir::ExprRef y1 = b.var("y1"), y2 = b.var("y2"), y3 = b.var("y3"),
              y4 = b.var("y4");
  ir::ExprRef t = c.time();
  ir::ExprRef u1 = c.call(ir::FuncKind::Sin, t),
              u2 = c.call(ir::FuncKind::Cos, t), u3 = c.mul(c.constant(2), t),
              u4 = c.call(ir::FuncKind::Exp, c.neg(t));
  b.eq(c.add(y1, y2), u1, "y1 + y2 = u1(t)");
  b.eq(c.add(c.add(y1, y2), y3), u2, "y1 + y2 + y3 = u2(t)");
  b.eq(c.add(c.add(y1, b.der(y3)), y4), u3, "y1 + der(y3) + y4 = u3(t)");
  b.eq(c.add(c.add(c.mul(c.constant(2), b.der(y1, 2)), b.der(y2, 2)),
             c.add(b.der(y3, 2), b.der(y4))),
       u4, "2*der(y1, 2) + der(y2, 2) + der(y3, 2) + der(y4) = u4(t)");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.structuralIndex, 2);
  // "we must prolongate twice the first two equations and the third once"
  EXPECT_EQ(timesOf(r, "y1 + y2 = u1(t)"), 2);
  EXPECT_EQ(timesOf(r, "y1 + y2 + y3 = u2(t)"), 2);
  EXPECT_EQ(timesOf(r, "y1 + der(y3) + y4 = u3(t)"), 1);
  EXPECT_EQ(r.differentiated.size(), 3u);
  // 5 differentiations, 5 dummy derivatives; the linear system has no
  // value-dependent choice: one state set.
  EXPECT_EQ(r.dummies.size(), 5u);
  EXPECT_EQ(r.stateSets.size(), 1u);
  ASSERT_TRUE(r.system);
  EXPECT_EQ(r.system->stateSets[0].residuals.size(),
            r.system->unknowns.size());
}

TEST(IndexReduction, RlcWithCapacitorVoltageSourceLoop) {
  Builder b("RLC", "rlc.lsd");
  auto &c = b.ctx();
  ir::ExprRef uC = b.var("C.v"), iC = b.var("C.i"), iL = b.var("L.i"),
              uL = b.var("L.v"), uR = b.var("R.v"), iS = b.var("V.i");
  ir::ExprRef C = b.param("C.C", 1e-3), L = b.param("L.L", 0.1),
              R = b.param("R.R", 10);
  b.eq(uC, c.call(ir::FuncKind::Sin, c.time()), "C.v = sin(time)");
  b.eq(c.mul(C, b.der(uC)), iC, "C * der(v) = i");
  b.eq(uR, c.mul(R, iL), "R.v = R * L.i");
  b.eq(c.mul(L, b.der(iL)), uL, "L * der(i) = v");
  b.eq(uC, c.add(uR, uL), "C.v = R.v + L.v");
  b.eq(iS, c.add(iC, iL), "V.i = C.i + L.i");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.structuralIndex, 2);
  EXPECT_EQ(timesOf(r, "C.v = sin(time)"), 1);
  EXPECT_EQ(r.dummies, (std::vector<std::string>{"der(C.v)"}));
  EXPECT_EQ(r.states, (std::vector<std::string>{"L.i"}));
  EXPECT_EQ(r.dof, 1);
}

TEST(IndexReduction, OdeAndIndexOne) {
  Builder b("Decay");
  auto &c = b.ctx();
  ir::ExprRef x = b.var("x", 1, true), z = b.var("z");
  b.eq(b.der(x), c.neg(z), "der(x) = -z");
  b.eq(z, c.mul(c.constant(2), x), "z = 2 * x");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  EXPECT_EQ(run.result.structuralIndex, 1);
  EXPECT_TRUE(run.result.differentiated.empty());
  EXPECT_EQ(run.result.states, (std::vector<std::string>{"x"}));
  EXPECT_EQ(run.result.bltBlocks, (std::vector<int>{1, 1}));
  EXPECT_EQ(run.result.init.dof, 0);
}

TEST(IndexReduction, RawMethodKeepsTheModelAsWritten) {
  Builder b("Pendulum", "pend.lsd");
  pendulumFirstOrder(b);
  passes::PipelineOptions opts = indexOneOptions();
  opts.method = passes::Method::Raw;
  Outcome run = analyze(b, opts);
  ASSERT_TRUE(run.result.system) << run.messages;
  const ir::DaeSystem &sys = *run.result.system;
  EXPECT_EQ(sys.unknowns.size(), 5u);
  EXPECT_EQ(sys.stateSets.size(), 1u);
  EXPECT_EQ(sys.stateSets[0].residuals.size(), 5u);
  int differential = 0;
  for (bool d : sys.stateSets[0].differential)
    differential += d;
  EXPECT_EQ(differential, 4);
  EXPECT_TRUE(sys.constraints.empty());
  // The index report is the same: raw only changes what is built.
  EXPECT_EQ(run.result.structuralIndex, 3);
}

TEST(IndexReduction, ShufflingDeclarationsChangesNothing) {
  Builder ref("Pendulum", "pend.lsd");
  pendulumFirstOrder(ref);
  Outcome base = analyze(ref);
  ASSERT_TRUE(base.ok);
  std::vector<int> perm{0, 1, 2, 3, 4};
  std::mt19937 rng(3);
  for (int trial = 0; trial < 6; ++trial) {
    std::shuffle(perm.begin(), perm.end(), rng);
    Builder b("Pendulum", "pend.lsd");
    pendulumFirstOrder(b, perm);
    Outcome run = analyze(b);
    ASSERT_TRUE(run.ok) << run.messages;
    EXPECT_EQ(run.result.states, base.result.states);
    EXPECT_EQ(run.result.dummies, base.result.dummies);
    EXPECT_EQ(run.result.bltBlocks, base.result.bltBlocks);
    EXPECT_EQ(run.result.stateSets.size(), base.result.stateSets.size());
    ASSERT_TRUE(run.result.system);
    std::vector<std::string> names, baseNames;
    for (const auto &u : run.result.system->unknowns)
      names.push_back(u.name);
    for (const auto &u : base.result.system->unknowns)
      baseNames.push_back(u.name);
    EXPECT_EQ(names, baseNames);
  }
}

TEST(IndexReduction, StateSelectDecidesTies) {
  // x and y enter the constraint with equal weight at the start point; a
  // stateSelect = prefer on x keeps x (and u) as states.
  Builder b("Pendulum", "pend.lsd");
  auto &c = b.ctx();
  double h = std::sqrt(0.5);
  b.var("x", h, false, ir::StateSelect::Prefer);
  b.var("y", -h);
  pendulumFirstOrder(b, {}, h, -h);
  (void)c;
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  EXPECT_EQ(run.result.states, (std::vector<std::string>{"u", "x"}));
}

TEST(IndexReduction, TwoBodyRodChain) {
  // Body 1 hangs from the origin, body 2 from body 1: two constraints, each
  // differentiated twice; four states (two per body); index 3.
  Builder b("Chain", "chain.lsd");
  auto &c = b.ctx();
  ir::ExprRef x1 = b.var("b1.x", 1), y1 = b.var("b1.y"), u1 = b.var("b1.u"),
              v1 = b.var("b1.v"), l1 = b.var("r1.f");
  ir::ExprRef x2 = b.var("b2.x", 2), y2 = b.var("b2.y"), u2 = b.var("b2.u"),
              v2 = b.var("b2.v"), l2 = b.var("r2.f");
  ir::ExprRef g = b.param("g", 9.81), two = c.constant(2);
  ir::ExprRef dx2 = c.sub(x2, x1), dy2 = c.sub(y2, y1);
  b.eq(c.add(c.pow(dx2, two), c.pow(dy2, two)), c.one(), "rod 2");
  b.eq(b.der(x2), u2, "der(b2.x) = b2.u");
  b.eq(b.der(y2), v2, "der(b2.y) = b2.v");
  b.eq(b.der(u2), c.neg(c.mul(l2, dx2)), "b2 x force");
  b.eq(b.der(v2), c.sub(c.neg(c.mul(l2, dy2)), g), "b2 y force");
  b.eq(c.add(c.pow(x1, two), c.pow(y1, two)), c.one(), "rod 1");
  b.eq(b.der(x1), u1, "der(b1.x) = b1.u");
  b.eq(b.der(y1), v1, "der(b1.y) = b1.v");
  b.eq(b.der(u1), c.add(c.neg(c.mul(l1, x1)), c.mul(l2, dx2)), "b1 x force");
  b.eq(b.der(v1), c.sub(c.add(c.neg(c.mul(l1, y1)), c.mul(l2, dy2)), g),
       "b1 y force");
  Outcome run = analyze(b);
  ASSERT_TRUE(run.ok) << run.messages;
  const AnalysisResult &r = run.result;
  EXPECT_EQ(r.structuralIndex, 3);
  EXPECT_EQ(timesOf(r, "rod 1"), 2);
  EXPECT_EQ(timesOf(r, "rod 2"), 2);
  EXPECT_EQ(r.dof, 4);
  // The rods make a block of two rows over four positions, chosen at run
  // time (and the velocities below it): every candidate's derivative is a
  // dummy, 8 for the differentiations and one more per state of the two
  // run-time sets.
  EXPECT_EQ(r.dummies.size(), 12u);
  ASSERT_TRUE(r.system);
  EXPECT_EQ(r.system->dynamicSets.size(), 2u);
  for (const ir::StateSet &st : r.system->stateSets)
    EXPECT_EQ(st.residuals.size(), r.system->unknowns.size());
}
