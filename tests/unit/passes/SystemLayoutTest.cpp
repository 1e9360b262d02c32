// The layout rule as the passes read it (SystemLayout), against hand-made
// systems: a state set's own slot keys (dynamic dummy derivatives) and
// sets without their own differential flags.
#include "passes/SystemStructure.h"

#include <gtest/gtest.h>

using namespace ldae;

namespace {

/// Two slots: slot 0 holds x (differential), slot 1 holds der(y) (a dummy
/// derivative). Set 1 swaps their meaning: slot 0 holds y, slot 1 der(x).
ir::DaeSystem twoSets() {
  ir::DaeSystem sys;
  sys.ctx = std::make_shared<ir::ExprContext>();
  ir::SystemUnknown x, dy;
  x.key = {0, 0};
  x.differential = true;
  dy.key = {1, 1};
  sys.unknowns = {x, dy};
  ir::StateSet s0, s1;
  s0.differential = {true, false};
  s1.differential = {true, false};
  s1.keys = {{1, 0}, {0, 1}};
  sys.stateSets = {s0, s1};
  return sys;
}

void expectRead(const passes::SystemLayout &l, ir::VarKey k, int unknown,
                bool derivative) {
  passes::SlotRead r = l.read(k);
  EXPECT_EQ(r.unknown, unknown) << "var " << k.var << " order " << k.order;
  EXPECT_EQ(r.derivative, derivative) << "var " << k.var << " order " << k.order;
}

} // namespace

TEST(SystemLayout, UnknownKeysInASetWithoutKeys) {
  ir::DaeSystem sys = twoSets();
  passes::SystemLayout l(sys, 0);
  expectRead(l, {0, 0}, 0, false); // x: y[0]
  expectRead(l, {0, 1}, 0, true);  // der(x): y'[0]
  expectRead(l, {1, 1}, 1, false); // der(y): y[1]
  expectRead(l, {1, 0}, -1, false); // y is no slot of set 0
}

TEST(SystemLayout, ASetsOwnKeysReplaceTheUnknownKeys) {
  ir::DaeSystem sys = twoSets();
  passes::SystemLayout l(sys, 1);
  expectRead(l, {1, 0}, 0, false); // y: y[0]
  expectRead(l, {1, 1}, 0, true);  // der(y): y'[0], not slot 1
  expectRead(l, {0, 1}, 1, false); // der(x): y[1]
  expectRead(l, {0, 0}, -1, false);
}

TEST(SystemLayout, FlagsOfTheUnknownsWhenASetHasNone) {
  ir::DaeSystem sys = twoSets();
  sys.stateSets[0].differential.clear();
  passes::SystemLayout l(sys, 0);
  expectRead(l, {0, 1}, 0, true); // x differential from unknowns[0]
  EXPECT_EQ(ir::setDifferential(sys, 0), (std::vector<bool>{true, false}));
  EXPECT_EQ(ir::anyDifferential(sys), (std::vector<bool>{true, false}));
}
