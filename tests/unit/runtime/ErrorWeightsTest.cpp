// ErrorWeights (runtime/src/integrators/ErrorWeights.cpp): each state's weight is the
// largest that it or a variable computed from it demands, and a computed
// variable's tolerance is floored at what the states' absolute tolerances
// and round-off leave of it. Hand models with the ABI's tested slots; the
// expected weights are worked out in each test.
#include "integrators/ErrorWeights.h"
#include "HandModels.h"

#include <cfloat>
#include <gtest/gtest.h>

using ldae::runtime::ErrorWeights;
using ldae::runtime::ModelEval;

namespace {

// Two states y1, y2 (nominal 1e-2 and 1, as in idaRoberts_dns) and one
// computed variable z, either y3 = 1 - y1 - y2 or a current 1000 y1.
const double kNominal[] = {1e-2, 1.0};
const int kColptr[] = {0, 1, 2}, kRowind[] = {0, 0};
const int kColptrCurrent[] = {0, 1, 1}, kRowindCurrent[] = {0};
const double kTestedNominal[] = {1.0};

int y3(double, const double *y, const double *, const double *, double *z) {
  z[0] = 1 - y[0] - y[1];
  return 0;
}
int y3Jac(double, const double *, const double *, const double *, double,
          double *v) {
  v[0] = v[1] = -1;
  return 0;
}
int current(double, const double *y, const double *, const double *,
            double *z) {
  z[0] = 1000 * y[0];
  return 0;
}
int currentJac(double, const double *, const double *, const double *,
               double, double *v) {
  v[0] = 1000;
  return 0;
}

ldae_model model(bool isCurrent) {
  ldae_model m = handmodels::blankModel("weights", 2);
  m.nominal = kNominal;
  m.n_tested = 1;
  m.tested_nominal = kTestedNominal;
  m.tested = isCurrent ? current : y3;
  m.tested_jacobian_csc = isCurrent ? currentJac : y3Jac;
  m.tested_jac_nnz = isCurrent ? 1 : 2;
  m.tested_jac_colptr = isCurrent ? kColptrCurrent : kColptr;
  m.tested_jac_rowind = isCurrent ? kRowindCurrent : kRowind;
  return m;
}

std::vector<double> weights(const ldae_model &m, double rtol, double atol,
                            std::vector<double> y) {
  ModelEval ev(m, {});
  ErrorWeights w(ev, rtol, atol);
  EXPECT_TRUE(w.propagates());
  std::vector<double> yp(2, 0.0), ewt(2);
  w.compute(0, y.data(), yp.data(), ewt.data());
  return ewt;
}

} // namespace

// Robertson at t = 0.4: y3 = 0.014966 demands 1e-4 * 0.014966 + 1e-6 of
// y1 and y2, 40x tighter than y1's own 1e-4 * 0.985 + 1e-8; y2's own
// (1e-6 + 3.4e-9) is already tighter and stays.
TEST(ErrorWeights, ComputedVariableRaisesItsStates) {
  std::vector<double> y = {0.985, 3.4e-5};
  std::vector<double> ewt = weights(model(false), 1e-4, 1e-6, y);
  double tol3 = 1e-4 * (1 - y[0] - y[1]) + 1e-6;
  EXPECT_NEAR(ewt[0], 1 / tol3, 1e-9 / tol3);
  EXPECT_NEAR(ewt[1], 1 / (1e-4 * y[1] + 1e-6), 1e-3);
  EXPECT_GT(ewt[0], 39 / (1e-4 * y[0] + 1e-8));
}

// A current i = 1000 v through a 1 mOhm resistor is not asked for more
// than v's own absolute tolerance carries (1000 atol_v = 1e-5, above its
// own 1e-6): v keeps its weight near 0 ...
TEST(ErrorWeights, AbsoluteToleranceOfTheStatesIsTheFloor) {
  std::vector<double> ewt = weights(model(true), 1e-4, 1e-6, {0.0, 0.5});
  EXPECT_DOUBLE_EQ(ewt[0], 1 / 1e-8);
  EXPECT_DOUBLE_EQ(ewt[1], 1 / (1e-4 * 0.5 + 1e-6));
  // ... and far from 0 the current's relative tolerance is v's own (its
  // atol, 1e-6 against 1000 v, adds a thousandth of v's 1e-8).
  ewt = weights(model(true), 1e-4, 1e-6, {2.0, 0.5});
  EXPECT_DOUBLE_EQ(ewt[0], 1000 / (1e-4 * 2000 + 1e-6));
  EXPECT_NEAR(ewt[0], 1 / (1e-4 * 2.0 + 1e-8), 1e-4 * ewt[0]);
}

// y3 = 0 from y1 = 1 at atol 1e-20: the demand stops at 100 units of
// round-off of y1, where the solvers can still step (u |y1| w1 = 0.01).
TEST(ErrorWeights, RoundoffIsTheFloor) {
  std::vector<double> ewt = weights(model(false), 1e-4, 1e-20, {1.0, 0.0});
  double floor = 1e-22 + 100 * DBL_EPSILON + 1e-20;
  EXPECT_NEAR(ewt[0], 1 / floor, 1e-9 / floor);
  EXPECT_LE(DBL_EPSILON * ewt[0], 0.01 + 1e-12);
}

// A model without tested variables keeps the solvers' own weights.
TEST(ErrorWeights, NoComputedVariables) {
  ldae_model m = handmodels::blankModel("plain", 2);
  m.nominal = kNominal;
  ModelEval ev(m, {});
  ErrorWeights w(ev, 1e-4, 1e-6);
  EXPECT_FALSE(w.propagates());
  ASSERT_EQ(w.atol().size(), 2u);
  EXPECT_DOUBLE_EQ(w.atol()[0], 1e-8);
  std::vector<double> y = {0.5, 2.0}, ewt(2);
  w.compute(0, y.data(), y.data(), ewt.data());
  EXPECT_DOUBLE_EQ(ewt[0], 1 / (1e-4 * 0.5 + 1e-8));
  EXPECT_DOUBLE_EQ(ewt[1], 1 / (1e-4 * 2.0 + 1e-6));
}
