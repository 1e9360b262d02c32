// Loop rolling (CodePlan.h, rollLoops): repeated equations become loops with
// affine or tabulated index columns, compute exactly what the straight-line
// code computes in every backend, and report a domain error inside a loop
// with the row of the failing iteration.
#include "TestUtil.h"

#include "codegen/CodePlan.h"
#include "codegen/LoopRolling.h"
#include "codegen/PlanLowering.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace ldae;
using namespace ldae::codegen;
using namespace ldae::codegen::testing;

namespace {

const PlanFunction &function(const CodePlan &plan, const std::string &name) {
  for (const PlanFunction &fn : plan.functions)
    if (fn.name == name)
      return fn;
  ADD_FAILURE() << "no function " << name;
  return plan.functions.front();
}

TEST(Loops, ChainResidualIsOneAffineLoop) {
  auto s = samples::chain(1000);
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  const PlanFunction &res = function(*plan, "residual_0");
  // Rows 1 and 1000 differ in shape (a missing neighbour, sin(t)).
  ASSERT_EQ(res.loops.size(), 1u);
  EXPECT_EQ(res.loops[0].count, 998u);
  EXPECT_EQ(res.stores.size(), 2u);
  for (const IndexColumn &c : res.loops[0].columns)
    EXPECT_TRUE(c.affine());
  // y[i-1], y[i], y[i+1], p[k], p[a]: y'[i], the output index and the row
  // are all i, y[i]'s column.
  EXPECT_EQ(res.loops[0].columns.size(), 5u);
  const PlanFunction &jac = function(*plan, "jac_csc_0");
  uint32_t rolled = 0;
  for (const PlanLoop &l : jac.loops)
    rolled += l.count;
  EXPECT_EQ(rolled + jac.stores.size(), 3 * 1000u - 2);
  EXPECT_GE(rolled, 3 * 998u);
}

TEST(Loops, SmallFunctionsStayStraightLine) {
  auto s = samples::chain(40);
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  // 40 residuals stay straight-line; the Jacobian's 118 entries do not.
  EXPECT_TRUE(function(*plan, "residual_0").loops.empty());
  EXPECT_FALSE(function(*plan, "jac_csc_0").loops.empty());
}

TEST(Loops, ShuffledLayoutReadsIndexTables) {
  auto s = samples::shuffledChain(1000);
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  // The hash-consed sums order their terms by creation, so scrambling the
  // declarations splits the interior rows into a few shapes.
  const PlanFunction &res = function(*plan, "residual_0");
  uint32_t rolled = 0;
  unsigned tables = 0;
  for (const PlanLoop &l : res.loops) {
    rolled += l.count;
    for (const IndexColumn &c : l.columns)
      if (!c.affine()) {
        ++tables;
        EXPECT_EQ(c.table.size(), l.count);
      }
  }
  EXPECT_EQ(rolled + res.stores.size(), 1000u);
  EXPECT_GE(rolled, 990u);
  EXPECT_GE(tables, 3u);
}

/// Loops and straight-line code agree in every function, in each backend.
void expectLoopsEqualStraightLine(const samples::SampleSystem &s) {
  CodegenOptions rolled, straight;
  straight.loops = false;
  for (bool jit : {true, false}) {
    rolled.jit = straight.jit = jit;
    auto a = compileOrDie(s.sys, rolled), b = compileOrDie(s.sys, straight);
    ASSERT_TRUE(a && b);
    for (unsigned seed = 1; seed <= 5; ++seed) {
      Point pt = randomPoint(a->model(), seed, -1.0, 1.0);
      EXPECT_EQ(compareEvaluations(evaluateAll(a->model(), pt),
                                   evaluateAll(b->model(), pt), 1e-15),
                "")
          << (jit ? "JIT" : "interpreter") << ", seed " << seed;
    }
  }
}

TEST(Loops, EqualStraightLineCode) {
  expectLoopsEqualStraightLine(samples::chain(300));
  expectLoopsEqualStraightLine(samples::shuffledChain(300));
}

TEST(Loops, LongSumIsOneReduction) {
  auto s = samples::logSum(200);
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  const PlanFunction &res = function(*plan, "residual_0");
  ASSERT_EQ(res.reductions.size(), 1u);
  // s - (log(x[1]) + log(x[2]) + ...): the inner sum starts from log(x[1])
  // and folds the 199 others.
  EXPECT_EQ(res.reductions[0].count, 199u);
  EXPECT_FALSE(res.reductions[0].subtract);
  unsigned reduces = 0;
  for (const PlanNode &n : res.nodes)
    reduces += n.op == OpCode::Reduce;
  EXPECT_EQ(reduces, 1u);
  // The same additions in the same order as the straight-line sum.
  expectLoopsEqualStraightLine(s);
}

/// The residual of one system in the JIT, the interpreter and emitted C.
class ThreeBackends {
public:
  explicit ThreeBackends(const samples::SampleSystem &s) : lib_(s.sys) {
    CodegenOptions interpOpts;
    interpOpts.jit = false;
    jit_ = compileOrDie(s.sys, {});
    interp_ = compileOrDie(s.sys, interpOpts);
  }
  bool ok() const { return jit_ && interp_ && lib_.model(); }
  const std::string &error() const { return lib_.error(); }
  /// Return codes of the residual at y (y' = 0) in each backend; r gets
  /// the emitted C's values.
  std::vector<int> codes(const std::vector<double> &y, std::vector<double> &r) {
    std::vector<double> yp(y.size(), 0.0);
    r.resize(y.size());
    std::vector<int> c;
    for (const ldae_model *m : {&jit_->model(), &interp_->model(), lib_.model()})
      c.push_back(m->state_sets[0].residual(0, y.data(), yp.data(), nullptr,
                                            r.data()));
    return c;
  }

private:
  std::unique_ptr<CompiledModel> jit_, interp_;
  CLibrary lib_;
};

TEST(Loops, DomainErrorInAReductionNamesItsRow) {
  ThreeBackends b(samples::logSum(200));
  ASSERT_TRUE(b.ok()) << b.error();
  std::vector<double> y(201, 1.5), r;
  EXPECT_EQ(b.codes(y, r), std::vector<int>({0, 0, 0}));
  EXPECT_NEAR(r[200], 1.5 - 200 * std::log(1.5), 1e-12); // s - sum
  y[120] = -1; // log(x[121]) in the sum of row 201
  EXPECT_EQ(b.codes(y, r), std::vector<int>({201, 201, 201}));
}

TEST(Loops, DomainErrorNamesTheFailingIteration) {
  auto s = samples::logChain(100);
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  ASSERT_EQ(function(*plan, "residual_0").loops.size(), 1u);
  ThreeBackends b(s);
  ASSERT_TRUE(b.ok()) << b.error();
  std::vector<double> y(100, 2.0), r;
  EXPECT_EQ(b.codes(y, r), std::vector<int>({0, 0, 0}));
  y[57] = -1;
  EXPECT_EQ(b.codes(y, r), std::vector<int>({58, 58, 58}));
  y[30] = 0; // log(0): the earlier row wins
  EXPECT_EQ(b.codes(y, r), std::vector<int>({31, 31, 31}));
}

} // namespace
