// The jump rule (LANGUAGE.md "Initial values", seed 002): the start and the
// state after an event move onto the consistent set along T(E, F) of the
// model as written, rebuilt from the reduced residual with dummy_of /
// original_row. Every expected value is computed by hand in the test.
#include "init/ConsistentInit.h"
#include "JumpModels.h"
#include "init/JumpRule.h"
#include "TestUtil.h"
#include "ldae/Simulation.h"
#include "numeric/WongSequence.h"

#include <cmath>
#include <gtest/gtest.h>
#include <sstream>

using namespace ldae::runtime;
using testutil::column;

namespace {

constexpr double C1 = 1e-3, C2 = 2e-3;

SimResult run(const ldae_model &m, double stop, std::ostringstream &log) {
  SimOptions o;
  o.start = 0;
  o.stop = stop;
  o.log = &log;
  o.progress = false;
  auto r = simulate(m, o);
  EXPECT_TRUE(r) << (r ? "" : r.error());
  return r ? *r : SimResult{};
}

double at(const SimResult &r, size_t row, const char *name) {
  int c = column(r, name);
  EXPECT_GE(c, 0) << name;
  return c >= 0 ? r.rows.at(row)[c] : NAN;
}

std::vector<double> params(const ldae_model &m) {
  return std::vector<double>(m.param_values, m.param_values + m.n_params);
}

} // namespace

TEST(JumpRule, TwoCapacitorsStartAtTheChargeConservingVoltage) {
  std::ostringstream log;
  SimResult r = run(jumpmodels::twoCapacitors(C1, C2, 10, 1), 1.0, log);
  ASSERT_EQ(r.status, 0) << r.failure << log.str();
  const double v = (C1 * 10 + C2 * 1) / (C1 + C2); // 4
  EXPECT_NEAR(at(r, 0, "v1"), v, 1e-12) << log.str();
  EXPECT_NEAR(at(r, 0, "v2"), v, 1e-12);
  EXPECT_NEAR(at(r, 0, "i"), 0.0, 1e-12);
  // Charge conserved, no current after: the voltages stay.
  EXPECT_NEAR(at(r, r.rows.size() - 1, "v1"), v, 1e-9);
  // T of the model as written: span(e_i, (-1/C1, 1/C2, 0)), index 2.
  EXPECT_NE(log.str().find("jump space T (dimension 2, index 2)"),
            std::string::npos)
      << log.str();
  EXPECT_NE(log.str().find("'v1' from 10 to 4"), std::string::npos)
      << log.str();
  EXPECT_NE(log.str().find("'v2' from 1 to 4"), std::string::npos);
}

TEST(JumpRule, TwoCapacitorsMatchTheProjectionAlongT) {
  // The pencil as written, E = diag(C1, C2, 0), and the Wong projection
  // onto V along T: the point the Newton iteration must reach.
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(3, 3), F(3, 3);
  E(0, 0) = C1;
  E(1, 1) = C2;
  F << 0, 0, -1, 0, 0, 1, -1, 1, 0;
  auto w = ldae::numeric::wongSequences(E, F);
  ASSERT_TRUE(w.regular);
  Eigen::Vector3d p =
      ldae::numeric::projectAlong(w, Eigen::Vector3d(10, 1, 0));
  EXPECT_NEAR(p(0), 4, 1e-12);
  EXPECT_NEAR(p(1), 4, 1e-12);

  // jumpDirections rebuilds the same T from the reduced Jacobian.
  ldae_model m = jumpmodels::twoCapacitors(C1, C2, 10, 1);
  ModelEval ev(m, params(m));
  Eigen::MatrixXd Fy, Ered;
  std::vector<double> y(m.start_y, m.start_y + 4), yp(4, 0.0);
  ASSERT_EQ(ev.jacobianParts(0, 0, y.data(), yp.data(), Fy, Ered), 0);
  JumpDirections jd =
      jumpDirections(m, 0, Ered, Fy, Eigen::VectorXd::Ones(4));
  EXPECT_TRUE(jd.written);
  EXPECT_EQ(jd.dim, 2);
  EXPECT_EQ(jd.dummies, 1);
  EXPECT_EQ(jd.index, 2);
  EXPECT_FALSE(jumpsAreAlgebraic(m, 0, jd));
  Eigen::MatrixXd Tw(4, 2);
  Tw << -1 / C1, 0, 1 / C2, 0, 0, 1, 0, 0;
  Eigen::MatrixXd both(4, 4);
  both << jd.basis.leftCols(2), Tw;
  EXPECT_EQ(ldae::numeric::rangeBasis(both, 1e-9).cols(), 2);
}

TEST(JumpRule, TwoCapacitorsJoinedByAnEvent) {
  // The state just before the switch closes: 10 V and 1 V.
  ldae_model m = jumpmodels::twoCapacitors(C1, C2, 4, 4);
  ModelEval ev(m, params(m));
  std::ostringstream log;
  InitOutcome out = reinitializeAfterEvent(ev, 0, 1.0, {10, 1, 0, 0},
                                           {0, 0, 0, 0}, {}, &log);
  ASSERT_TRUE(out.ok) << out.failure;
  EXPECT_NEAR(out.y[0], 4, 1e-12);
  EXPECT_NEAR(out.y[1], 4, 1e-12);
  EXPECT_NEAR(out.y[2], 0, 1e-12);
  EXPECT_TRUE(out.written);
  EXPECT_EQ(out.jumped, 2);
  EXPECT_NE(log.str().find("re-initialization at t = 1 moved:\n  'v1' from "
                           "10 to 4"),
            std::string::npos)
      << log.str();
}

TEST(JumpRule, ReinitTargetHeldLeavesNoStepAlongT) {
  // reinit(v1, 7) at 4 V: the only direction along T that meets v1 = v2
  // moves v1, which the reinit holds; the nearest point moves v2 to 7.
  ldae_model m = jumpmodels::twoCapacitors(C1, C2, 4, 4);
  ModelEval ev(m, params(m));
  std::ostringstream log;
  InitOutcome out = reinitializeAfterEvent(ev, 0, 2.0, {7, 4, 0, 0},
                                           {0, 0, 0, 0}, {0}, &log);
  ASSERT_TRUE(out.ok) << out.failure;
  EXPECT_EQ(out.y[0], 7.0);
  EXPECT_NEAR(out.y[1], 7, 1e-12);
  EXPECT_TRUE(out.nearestPoint);
  EXPECT_EQ(out.jumped, 1);
  EXPECT_NE(log.str().find("warning: the start values cannot be made "
                           "consistent along the jump directions"),
            std::string::npos)
      << log.str();
}

TEST(JumpRule, PendulumVelocityLosesItsNormalComponent) {
  // On the circle at 0.5 rad; velocity 2 along the tangent t plus 0.7
  // along the outward normal n. T of the pendulum as written at a point:
  // radial position, radial velocity, lam. So the position stays, the
  // normal velocity is removed, the tangential one kept (not "keep the
  // states x, u": u would keep its start value).
  const double th = 0.5, g = 9.81;
  const Eigen::Vector2d t(std::cos(th), std::sin(th)),
      n(std::sin(th), -std::cos(th));
  Eigen::Vector2d w = 2 * t + 0.7 * n, kept = 2 * t;
  std::ostringstream log;
  SimResult r = run(jumpmodels::dummyPendulum(th, w(0), w(1)), 0, log);
  ASSERT_EQ(r.status, 0) << r.failure << log.str();
  EXPECT_NEAR(at(r, 0, "x"), std::sin(th), 1e-12);
  EXPECT_NEAR(at(r, 0, "y"), -std::cos(th), 1e-12);
  EXPECT_NEAR(at(r, 0, "u"), kept(0), 1e-12) << log.str();
  EXPECT_NEAR(at(r, 0, "v"), kept(1), 1e-12);
  // The hidden constraint: lam = |v|^2 - g y over L^2 = 4 + g cos(0.5).
  EXPECT_NEAR(at(r, 0, "lam"), 4 + g * std::cos(th), 1e-10);
  EXPECT_NE(log.str().find("jump space T (dimension 3, index 3)"),
            std::string::npos)
      << log.str();
}

TEST(JumpRule, InductorCutsetConservesFlux) {
  // R-L1-L2-C in series from i1 = 2, i2 = -1: one current after the jump,
  // i = (L1 i1 + L2 i2)/(L1 + L2) = -0.25; the capacitor voltage is free
  // (not in T) and keeps 5; then L1 i' + L2 i' = -(vC + R i).
  const double LLCR[4] = {0.1, 0.3, 1e-3, 10};
  std::ostringstream log;
  SimResult r =
      run(jumpmodels::inductorCutset(LLCR, 2, -1, 5), 0, log);
  ASSERT_EQ(r.status, 0) << r.failure << log.str();
  const double i = (0.1 * 2 + 0.3 * -1) / 0.4;
  const double di = -(5 + 10 * i) / 0.4;
  EXPECT_NEAR(at(r, 0, "i1"), i, 1e-12) << log.str();
  EXPECT_NEAR(at(r, 0, "i2"), i, 1e-12);
  EXPECT_EQ(at(r, 0, "vC"), 5.0);
  EXPECT_NEAR(at(r, 0, "vL1"), 0.1 * di, 1e-12);
  EXPECT_NEAR(at(r, 0, "vL2"), 0.3 * di, 1e-12);
}

TEST(JumpRule, IndexOneKeepsTheDifferentialValues) {
  // Tables saying "no dummy, every row as written": the set's own pencil,
  // the index-1 path, x kept and z solved as before.
  static const int dummy[] = {-1, -1}, original[] = {1, 1};
  static jumpmodels::Tables tables{{dummy}, {original}};
  ldae_model m = handmodels::index1Init(false);
  tables.attach(m);
  EXPECT_FALSE(hasWrittenPencil(m, 0));
  std::ostringstream log;
  SimResult r = run(m, 0, log);
  ASSERT_EQ(r.status, 0) << r.failure;
  EXPECT_EQ(at(r, 0, "x"), 1.0);
  EXPECT_NEAR(at(r, 0, "z"), 2.0, 1e-8);
  EXPECT_NE(log.str().find("index-1 structure"), std::string::npos)
      << log.str();

  // After an event: x = 3 is kept, z = 2 x solved (to the Newton's 1e-10).
  ModelEval ev(m, {});
  InitOutcome out =
      reinitializeAfterEvent(ev, 0, 1.0, {3, 2}, {0, 0}, {}, nullptr);
  ASSERT_TRUE(out.ok) << out.failure;
  EXPECT_EQ(out.y[0], 3.0);
  EXPECT_NEAR(out.y[1], 6.0, 1e-10);
  EXPECT_EQ(out.jumped, 1);
}

TEST(JumpRule, LargeIndexOneModelAfterAnEventIsSparse) {
  // 40 unknowns (above the dense threshold): reinit(y1, 3) held, z1 = y1
  // solved, every other value kept; fixed start values do not apply.
  ldae_model m = handmodels::decayChain(20);
  ModelEval ev(m, params(m));
  std::vector<double> y(40, 1.0), yp(40, 0.0);
  for (int i = 0; i < 20; ++i)
    yp[2 * i] = -0.1 * (i + 1);
  y[0] = 3;
  std::ostringstream log;
  InitOutcome out = reinitializeAfterEvent(ev, 0, 1.0, y, yp, {0}, &log);
  ASSERT_TRUE(out.ok) << out.failure;
  EXPECT_EQ(out.y[0], 3.0);
  EXPECT_NEAR(out.y[1], 3.0, 1e-10);
  EXPECT_NEAR(out.yp[0], -0.3, 1e-10);
  for (int i = 2; i < 40; ++i)
    EXPECT_NEAR(out.y[i], 1.0, 1e-12) << i;
  EXPECT_EQ(out.jumped, 1);
  EXPECT_NE(log.str().find("'z1' from 1 to 3"), std::string::npos)
      << log.str();
}

TEST(JumpRule, HeldCoordinatesLeaveNoRoundOffToSolve) {
  // The pendulum at rest at 0.5 rad with x and u held (reinit targets, or
  // fixed start values): T ∩ {x, u held} is lam and the dummies; the
  // SVDs' round-off on the held coordinates must not make the position
  // constraint look unsolvable (it would fall back to the nearest point).
  const double th = 0.5;
  ldae_model m = jumpmodels::dummyPendulum(th, 0, 0);
  ModelEval ev(m, params(m));
  std::vector<double> y(m.start_y, m.start_y + 7), yp(7, 0.0);
  std::ostringstream log;
  InitOutcome out = reinitializeAfterEvent(ev, 0, 0.0, y, yp, {0, 2}, &log);
  ASSERT_TRUE(out.ok) << out.failure;
  EXPECT_FALSE(out.nearestPoint) << log.str();
  EXPECT_EQ(out.jumped, 2); // lam and the dummy der(v)
  EXPECT_NEAR(out.y[4], 9.81 * std::cos(th), 1e-10);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(out.y[i], y[i]) << m.var_names[i];
}
