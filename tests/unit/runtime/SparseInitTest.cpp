// Sparse consistent initialization (n > LDAE_DENSE_THRESHOLD): the index-1
// test on the CSC Jacobian with KLU, and the sparse index-1 Newton
// iteration, which must land on the same point as the dense Newton along
// T(E, F); a 2000-unknown chain initializes without dense matrices.
#include "init/ConsistentInit.h"
#include "HandModels.h"
#include "init/SparseInit.h"
#include "ldae/Simulation.h"

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
    if (m.state_sets[0].is_differential[i]) {
      EXPECT_EQ(sparse.y[i], y0[i]) << i; // differential values stay
    }
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
  // time, the unknowns, then the parameters as constant columns.
  ASSERT_EQ(r->rows[0].size(), size_t(m.n + 1 + m.n_params));
  // The reported y: differential values kept, algebraic equations met to
  // IDACalcIC's tolerance (they do not involve y').
  std::vector<double> y(r->rows[0].begin() + 1,
                        r->rows[0].begin() + 1 + m.n),
      yp(m.n, 0.0), res(m.n);
  ASSERT_EQ(ev.residual(0, 0.0, y.data(), yp.data(), res.data()), 0);
  for (int i = 0; i < m.n; i += 2) {
    ASSERT_EQ(y[i], m.start_y[i]) << i;
    ASSERT_LE(std::fabs(res[i + 1]), 1e-6) << i + 1;
  }
}

// ---- Initial equations and fixed algebraic values, sparse -------------
// 18 pairs (x_i differential, z_i algebraic), 36 unknowns (just above
// LDAE_DENSE_THRESHOLD): der(x_i) = -x_i + z_i, z_i = 2 x_i^2, with
//  - initial equation der(x_0) = 0: x_0 moves from 0.4 to the root 0.5;
//  - z_1 fixed at 0.18: x_1 moves from 0.25 to 0.3;
//  - initial equation x_2 + x_3 = 1: a block where the matching could move
//    either value; the minimum-norm (nominal-scaled) step moves both;
//  - the other x_i keep their start values.
namespace tied {
constexpr int kPairs = 18, kN = 2 * kPairs;
struct Store {
  double y0[kN], yp0[kN], nominal[kN];
  int fixed[kN], diff[kN];
  int colptr[kN + 1], rowind[2 * kN];
  int icolptr[kN + 1], irowind[3];
  const char *names[kN];
  std::string text[kN];
  ldae_state_set set{};
};

inline int res(double, const double *y, const double *yp, const double *,
               double *r) {
  for (int i = 0; i < kPairs; ++i) {
    double x = y[2 * i], z = y[2 * i + 1];
    r[2 * i] = -x + z - yp[2 * i];
    r[2 * i + 1] = z - 2 * x * x;
  }
  return 0;
}
inline int jacCsc(double, const double *y, const double *, const double *,
                  double cj, double *v) {
  for (int i = 0; i < kPairs; ++i) {
    v[4 * i] = -1 - cj;       // d r_2i / d x_i
    v[4 * i + 1] = -4 * y[2 * i]; // d r_2i+1 / d x_i
    v[4 * i + 2] = 1;         // d r_2i / d z_i
    v[4 * i + 3] = 1;         // d r_2i+1 / d z_i
  }
  return 0;
}
inline int initRes(double, const double *y, const double *yp, const double *,
                   double *g) {
  g[0] = yp[0];
  g[1] = y[4] + y[6] - 1;
  return 0;
}
inline int initJacCsc(double, const double *, const double *, const double *,
                      double *gy, double *gyp) {
  // Pattern: (row 0, col 0), (row 1, col 4), (row 1, col 6).
  gy[0] = 0, gyp[0] = 1;
  gy[1] = 1, gyp[1] = 0;
  gy[2] = 1, gyp[2] = 0;
  return 0;
}

/// The model with x_2, x_3 starting at (a, b) and x_3's nominal `nom3`;
/// `fixFree` fixes the x_i that nothing else determines.
inline ldae_model model(Store &s, double a, double b, double nom3,
                        double z1 = 0.18, bool fixFree = false) {
  for (int i = 0; i < kPairs; ++i) {
    s.y0[2 * i] = 0.1 + 0.01 * i;
    s.y0[2 * i + 1] = 0;
    s.diff[2 * i] = 1;
    s.diff[2 * i + 1] = 0;
    s.text[2 * i] = "x[" + std::to_string(i) + "]";
    s.text[2 * i + 1] = "z[" + std::to_string(i) + "]";
  }
  for (int j = 0; j < kN; ++j) {
    s.yp0[j] = 0;
    s.nominal[j] = 1;
    s.fixed[j] = 0;
    s.names[j] = s.text[j].c_str();
    s.colptr[j] = 2 * j;
    s.rowind[2 * j] = j - j % 2;
    s.rowind[2 * j + 1] = j - j % 2 + 1;
  }
  s.colptr[kN] = 2 * kN;
  for (int i = 4; fixFree && i < kPairs; ++i)
    s.fixed[2 * i] = 1;
  s.y0[0] = 0.4;
  s.y0[2] = 0.25;
  s.y0[3] = z1;
  s.fixed[3] = 1;
  s.y0[4] = a;
  s.y0[6] = b;
  s.nominal[6] = nom3;
  for (int j = 0; j <= kN; ++j)
    s.icolptr[j] = j < 1 ? 0 : j < 5 ? 1 : j < 7 ? 2 : 3;
  s.irowind[0] = 0, s.irowind[1] = 1, s.irowind[2] = 1;
  s.set = ldae_state_set{};
  s.set.is_differential = s.diff;
  s.set.residual = res;
  s.set.jacobian_csc = jacCsc;
  s.set.jac_nnz = 2 * kN;
  s.set.jac_colptr = s.colptr;
  s.set.jac_rowind = s.rowind;
  ldae_model m = handmodels::makeModel("Tied", kN, s.names, s.y0, s.yp0,
                                       s.nominal, s.fixed, &s.set);
  m.n_init = 2;
  m.init_residual = initRes;
  m.init_jac_nnz = 3;
  m.init_jac_colptr = s.icolptr;
  m.init_jac_rowind = s.irowind;
  m.init_jacobian_csc = initJacCsc;
  return m;
}
} // namespace tied

// Where the consistent point is unique, the sparse path lands where the
// dense one does. (With initial equations the dense path's step is the
// minimum norm of the moves of y and y' together, so it also moves
// differential values no condition ties, to make y' move less; the sparse
// path keeps those, as LANGUAGE.md says. Hence the free x_i are fixed here.)
TEST(SparseInit, InitialEquationsAndFixedValuesAsDensePath) {
  tied::Store s;
  ldae_model m = tied::model(s, 0.2, 0.2, 1.0, 0.18, true);
  ModelEval ev = evalOf(m);
  ASSERT_TRUE(usesSparseInit(ev));
  EXPECT_FALSE(isPlainIndexOne(ev, 0, 0.0, m.start_y, m.start_yp));
  std::vector<double> y0 = startY(m), yp0 = startYp(m);
  InitOutcome sparse = initializeSparse(ev, 0, 0.0, y0, yp0);
  InitOutcome dense = initializeAlongJumps(ev, 0, 0.0, y0, yp0, nullptr);
  ASSERT_TRUE(sparse.ok) << sparse.failure;
  ASSERT_TRUE(dense.ok) << dense.failure;
  EXPECT_FALSE(dense.nearestPoint);
  // The values of the rule: x_0 at the root 0.5 of 2x^2 - x, x_1 where
  // 2 x^2 = 0.18, the tied pair symmetric, the rest kept.
  EXPECT_NEAR(sparse.y[0], 0.5, 1e-12);
  EXPECT_NEAR(sparse.y[2], 0.3, 1e-12);
  EXPECT_NEAR(sparse.y[4], 0.5, 1e-12);
  EXPECT_NEAR(sparse.y[6], 0.5, 1e-12);
  for (int i = 4; i < tied::kPairs; ++i)
    EXPECT_EQ(sparse.y[2 * i], y0[2 * i]) << i;
  EXPECT_EQ(sparse.moved, 3);
  EXPECT_EQ(sparse.kept, 1);
  EXPECT_EQ(sparse.projected, 1);
  for (int j = 0; j < m.n; ++j) {
    EXPECT_NEAR(sparse.y[j], dense.y[j], 1e-10) << j;
    EXPECT_NEAR(sparse.yp[j], dense.yp[j], 1e-10) << j;
  }
  EXPECT_LE(maxResidual(ev, sparse.y, sparse.yp), 1e-12);
}

TEST(SparseInit, TiedDifferentialValuesMoveByTheMinimumNormStep) {
  // x_2 + x_3 = 1 from (0.1, 0.3): both move by 0.3. With x_3's nominal 2
  // the scaled distance (dx_2)^2 + (dx_3 / 2)^2 is smallest at
  // dx_2 = 0.6 / 5, dx_3 = 4 * 0.6 / 5.
  tied::Store s;
  for (double nom : {1.0, 2.0}) {
    ldae_model m = tied::model(s, 0.1, 0.3, nom);
    ModelEval ev = evalOf(m);
    InitOutcome init = initializeSparse(ev, 0, 0.0, startY(m), startYp(m));
    ASSERT_TRUE(init.ok) << init.failure;
    double d2 = 0.6 / (1 + nom * nom);
    EXPECT_NEAR(init.y[4], 0.1 + d2, 1e-12) << nom;
    EXPECT_NEAR(init.y[6], 0.3 + 0.6 - d2, 1e-12) << nom;
  }
}

TEST(SparseInit, FailureNamesTheBlock) {
  // z_1 fixed at -1: 2 x_1^2 = -1 has no real root.
  tied::Store s;
  ldae_model m = tied::model(s, 0.2, 0.2, 1.0, -1.0);
  ModelEval ev = evalOf(m);
  InitOutcome init = initializeSparse(ev, 0, 0.0, startY(m), startYp(m));
  ASSERT_FALSE(init.ok);
  EXPECT_TRUE(init.applicable);
  EXPECT_NE(init.failure.find("a block of 1 equation was not solved: "
                              "equation 4; iteration variables 'x[1]' "
                              "(guess 0.25, reached"),
            std::string::npos)
      << init.failure;
  EXPECT_NE(init.failure.find("give start values near the solution for "
                              "'x[1]', or check the fixed values and "
                              "initial equations"),
            std::string::npos)
      << init.failure;
  // Through simulate(): status 3 with that message.
  SimOptions o;
  o.start = 0;
  o.stop = 0;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  EXPECT_NE(r->failure.find("initialization failed at t = 0: no consistent "
                            "initial point: a block of 1 equation"),
            std::string::npos)
      << r->failure;
}

TEST(SparseInit, SimulatorUsesTheSparsePath) {
  tied::Store s;
  ldae_model m = tied::model(s, 0.1, 0.3, 1.0);
  SimOptions o;
  o.start = 0;
  o.stop = 0;
  o.progress = false;
  std::ostringstream log;
  o.log = &log;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_NE(log.str().find("sparse Newton iteration (KLU) on the residuals, "
                           "fixed values and initial equations; 15 "
                           "differential values kept, 3 moved by the "
                           "conditions (1 in minimum-norm blocks)"),
            std::string::npos)
      << log.str();
  EXPECT_NEAR(r->rows[0][1 + 4], 0.4, 1e-12);
  EXPECT_NEAR(r->rows[0][1 + 6], 0.6, 1e-12);
}
