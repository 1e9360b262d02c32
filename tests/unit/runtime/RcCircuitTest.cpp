// The RC circuit against its analytic solution v = V0 (1 - exp(-t / RC)).
#include "HandModels.h"
#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"
#include "TestUtil.h"

#include <cmath>
#include <gtest/gtest.h>
#include <sstream>

using namespace ldae::runtime;

TEST(RcCircuit, AnalyticSolution) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.interval = 0.01;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  // The model's experiment says stop = 5; start defaults to 0.
  ASSERT_EQ(r->rows.size(), 501u);
  EXPECT_DOUBLE_EQ(r->rows.back()[0], 5.0);
  int v = testutil::column(*r, "C.v"), i = testutil::column(*r, "R.i");
  ASSERT_GT(v, 0);
  ASSERT_GT(i, 0);
  double worst = 0;
  for (const auto &row : r->rows) {
    double t = row[0], exact = 1 - std::exp(-t);
    worst = std::max(worst, std::fabs(row[v] - exact));
    EXPECT_NEAR(row[i], std::exp(-t) / 1000, 1e-11);
  }
  EXPECT_LE(worst, 1e-8);
  EXPECT_FALSE(r->stats.sparse);
  EXPECT_GT(r->stats.steps, 0);
  EXPECT_GT(r->stats.jacobianEvals, 0);
}

TEST(RcCircuit, ParameterOverrideAndOutputSelection) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.stop = 1;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.params["R"] = 500; // RC = 0.5
  o.outputs = {"C.v"};
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->columns, (std::vector<std::string>{"time", "C.v"}));
  EXPECT_NEAR(r->rows.back()[1], 1 - std::exp(-2.0), 1e-8);
}

TEST(RcCircuit, UnknownNamesAreErrors) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.outputs = {"C.w"};
  auto r = simulate(m, o);
  ASSERT_FALSE(r);
  // Parameters are columns too: C is close to C.w.
  EXPECT_EQ(r.error(), "unknown output 'C.w'; did you mean 'C.v', 'C'?");
  SimOptions p;
  p.params["Rr"] = 1;
  auto q = simulate(m, p);
  ASSERT_FALSE(q);
  EXPECT_EQ(q.error(), "unknown parameter 'Rr'; did you mean 'R'?");
  SimOptions s;
  s.stop = -1;
  EXPECT_FALSE(simulate(m, s));
}

TEST(RcCircuit, LogReportsInitialization) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.stop = 0.1;
  std::ostringstream log;
  o.log = &log;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r);
  // i starts at 0 but must be V0 / R: it moves, v (fixed) does not.
  EXPECT_NE(log.str().find("'R.i' from 0 to 0.001"), std::string::npos)
      << log.str();
  EXPECT_EQ(log.str().find("'C.v' from"), std::string::npos) << log.str();
}

namespace {
// Reported variables: the resistor's power R i^2 and the capacitor's
// charge C v.
int rcOutputs(double, const double *y, const double *, const double *p,
              double *out) {
  out[0] = p[0] * y[1] * y[1];
  out[1] = p[1] * y[0];
  return 0;
}
} // namespace

TEST(RcCircuit, OutputsFunctionGivesTheColumns) {
  static const char *outNames[] = {"R.p", "C.q"};
  ldae_model m = handmodels::rcCircuit();
  m.n_outputs = 2;
  m.output_names = outNames;
  m.outputs = rcOutputs;
  SimOptions o;
  o.stop = 1;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  // The outputs, then every parameter as a constant column.
  ASSERT_EQ(r->columns, (std::vector<std::string>{"time", "R.p", "C.q", "R",
                                                  "C", "V0"}));
  for (const auto &row : r->rows) {
    double t = row[0], i = std::exp(-t) / 1000;
    EXPECT_NEAR(row[1], 1000 * i * i, 1e-12);
    EXPECT_NEAR(row[2], 1e-3 * (1 - std::exp(-t)), 1e-11);
  }
  // Selection is by output name now; unknowns are not columns.
  o.outputs = {"C.v"};
  auto bad = simulate(m, o);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error(), "unknown output 'C.v'; did you mean 'C.q', 'C'?");
}
