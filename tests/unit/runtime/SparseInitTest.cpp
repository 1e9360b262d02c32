// Sparse consistent initialization (n > LDAE_DENSE_THRESHOLD): the index-1
// test on the CSC Jacobian with KLU, and the sparse index-1 Newton
// iteration, which must land on the same point as the dense Newton along
// T(E, F); a 2000-unknown chain initializes without dense matrices.
#include "ConsistentInit.h"
#include "HandModels.h"
#include "Simulator.h"

#include <cmath>
#include <gtest/gtest.h>
#include <sstream>

using namespace ldae::runtime;

namespace {
ModelEval evalOf(const ldae_model &m) {
  return ModelEval(m, std::vector<double>(m.param_values,
                                          m.param_values + m.n_params));
}

std::vector<double> startY(const ldae_model &m) {
  return std::vector<double>(m.start_y, m.start_y + m.n);
}
std::vector<double> startYp(const ldae_model &m) {
  return std::vector<double>(m.start_yp, m.start_yp + m.n);
}

/// max |F(t, y, y')| of state set 0.
double maxResidual(const ModelEval &ev, const std::vector<double> &y,
                   const std::vector<double> &yp) {
  std::vector<double> r(ev.n());
  EXPECT_EQ(ev.residual(0, 0.0, y.data(), yp.data(), r.data()), 0);
  double worst = 0;
  for (double v : r)
    worst = std::max(worst, std::fabs(v));
  return worst;
}
} // namespace

TEST(SparseInit, IndexOneTestOnTheCscJacobian) {
  ldae_model m = handmodels::coupledChain(20); // 40 unknowns: sparse path
  ModelEval ev = evalOf(m);
  ASSERT_TRUE(usesSparseInit(ev));
  EXPECT_TRUE(isPlainIndexOne(ev, 0, 0.0, m.start_y, m.start_yp));

  // z_1 declared differential: its E column is zero, so [E_d F_a] has a
  // zero column (KLU finds no pivot).
  std::vector<int> diff(m.state_sets[0].is_differential,
                        m.state_sets[0].is_differential + m.n);
  ldae_state_set set = m.state_sets[0];
  set.is_differential = diff.data();
  ldae_model bad = m;
  bad.state_sets = &set;
  diff[1] = 1;
  ModelEval evBad = evalOf(bad);
  EXPECT_FALSE(isPlainIndexOne(evBad, 0, 0.0, m.start_y, m.start_yp));
  // y_1 declared algebraic: E does not vanish on an algebraic column.
  diff[1] = 0;
  diff[0] = 0;
  EXPECT_FALSE(isPlainIndexOne(evBad, 0, 0.0, m.start_y, m.start_yp));
}

TEST(SparseInit, SameConsistentPointAsDenseNewton) {
  ldae_model m = handmodels::coupledChain(20);
  ModelEval ev = evalOf(m);
  std::vector<double> y0 = startY(m), yp0 = startYp(m);
  InitOutcome sparse = initializeIndexOne(ev, 0, 0.0, y0, yp0);
  InitOutcome dense = initializeAlongJumps(ev, 0, 0.0, y0, yp0, nullptr);
  ASSERT_TRUE(sparse.ok) << sparse.failure;
  ASSERT_TRUE(dense.ok) << dense.failure;
  EXPECT_FALSE(dense.nearestPoint);
  EXPECT_EQ(dense.index, 1);
  EXPECT_EQ(sparse.jumpDim, dense.jumpDim);
  for (int i = 0; i < m.n; ++i) {
    EXPECT_NEAR(sparse.y[i], dense.y[i], 1e-12) << i;
    EXPECT_NEAR(sparse.yp[i], dense.yp[i], 1e-12) << i;
    if (m.state_sets[0].is_differential[i])
      EXPECT_EQ(sparse.y[i], y0[i]) << i; // differential values stay
  }
  EXPECT_LE(maxResidual(ev, sparse.y, sparse.yp), 1e-12);
  // The start point really was inconsistent: z moved.
  EXPECT_GT(std::fabs(sparse.y[1] - y0[1]), 0.1);
}

TEST(SparseInit, LargeChainNewton) {
  ldae_model m = handmodels::coupledChain(1000); // 2000 unknowns
  ModelEval ev = evalOf(m);
  std::vector<double> y0 = startY(m), yp0 = startYp(m);
  ASSERT_TRUE(isPlainIndexOne(ev, 0, 0.0, y0.data(), yp0.data()));
  InitOutcome init = initializeIndexOne(ev, 0, 0.0, y0, yp0);
  ASSERT_TRUE(init.ok) << init.failure;
  EXPECT_EQ(init.jumpDim, 1000);
  EXPECT_LE(maxResidual(ev, init.y, init.yp), 1e-10);
  for (int i = 0; i < m.n; i += 2)
    ASSERT_EQ(init.y[i], y0[i]) << i;
}

TEST(SparseInit, LargeChainSimulatorStart) {
  // Through simulate(): the sparse index-1 test, then IDACalcIC with KLU.
  ldae_model m = handmodels::coupledChain(1000);
  ModelEval ev = evalOf(m);
  SimOptions o;
  o.start = 0;
  o.stop = 0;
  std::ostringstream log;
  o.log = &log;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_TRUE(r->stats.sparse);
  EXPECT_NE(log.str().find("index-1 structure"), std::string::npos)
      << log.str();
  ASSERT_EQ(r->rows.size(), 1u);
  ASSERT_EQ(r->rows[0].size(), size_t(m.n + 1));
  // The reported y: differential values kept, algebraic equations met to
  // IDACalcIC's tolerance (they do not involve y').
  std::vector<double> y(r->rows[0].begin() + 1, r->rows[0].end()),
      yp(m.n, 0.0), res(m.n);
  ASSERT_EQ(ev.residual(0, 0.0, y.data(), yp.data(), res.data()), 0);
  for (int i = 0; i < m.n; i += 2) {
    ASSERT_EQ(y[i], m.start_y[i]) << i;
    ASSERT_LE(std::fabs(res[i + 1]), 1e-6) << i + 1;
  }
}
