// Consistent initialization: free differential values keep their start
// values, algebraic ones are solved; an index-2 linear model moves its start
// vector along the jump space T(E, F) computed by the Wong sequence.
#include "HandModels.h"
#include "ldae/Simulation.h"
#include "numeric/WongSequence.h"

#include <cmath>
#include <gtest/gtest.h>
#include <sstream>

using namespace ldae::runtime;

namespace {
SimResult initOnly(const ldae_model &m, std::ostringstream &log) {
  SimOptions o;
  o.start = 0;
  o.stop = 0;
  o.log = &log;
  o.progress = false;
  auto r = simulate(m, o);
  EXPECT_TRUE(r) << (r ? "" : r.error());
  return r ? *r : SimResult{};
}
} // namespace

TEST(ConsistentInit, FreeDifferentialKeepsStartValue) {
  std::ostringstream log;
  SimResult r = initOnly(handmodels::index1Init(false), log);
  ASSERT_EQ(r.status, 0) << r.failure;
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_EQ(r.rows[0][1], 1.0);         // x kept
  EXPECT_NEAR(r.rows[0][2], 2.0, 1e-8); // z = 2 x, solved to rtol
  EXPECT_NE(log.str().find("index-1 structure"), std::string::npos);
  EXPECT_NE(log.str().find("'z' from 5 to 2"), std::string::npos) << log.str();
  EXPECT_EQ(log.str().find("'x' from"), std::string::npos) << log.str();
}

TEST(ConsistentInit, FixedAlgebraicFreesTheDifferential) {
  // z = 4 fixed: T = span(e_z) minus the fixed coordinate leaves no step,
  // so the nearest consistent point moves x to 2, with a warning.
  std::ostringstream log;
  SimResult r = initOnly(handmodels::index1Init(true), log);
  ASSERT_EQ(r.status, 0) << r.failure;
  EXPECT_NEAR(r.rows[0][1], 2.0, 1e-12);
  EXPECT_EQ(r.rows[0][2], 4.0);
  EXPECT_NE(log.str().find("warning: the start values cannot be made "
                           "consistent along the jump directions"),
            std::string::npos)
      << log.str();
}

TEST(ConsistentInit, IndexTwoMovesAlongWongJumpSpace) {
  // x1' = x2, x3' = x2 - x3, 0 = x1 - c from (2, 3, 1), c = 0.5.
  const double a = 2, b = 3, c3 = 1, c = 0.5;
  std::ostringstream log;
  SimResult r = initOnly(handmodels::index2Linear(a, b, c3, c), log);
  ASSERT_EQ(r.status, 0) << r.failure;
  // By hand: consistent set {x1 = c, x2 = 0}; T = span(e1 + e3, e2); so
  // x3 moves with x1 by the same impulse: x3 = c3 - (a - c).
  EXPECT_NEAR(r.rows[0][1], c, 1e-10);
  EXPECT_NEAR(r.rows[0][2], 0.0, 1e-10);
  EXPECT_NEAR(r.rows[0][3], c3 - (a - c), 1e-10);
  EXPECT_NE(log.str().find("jump space T (dimension 2, index 2)"),
            std::string::npos)
      << log.str();
  // The same point as projecting along T onto V for the shifted linear
  // system (x - (c, 0, 0) lies in V).
  Eigen::MatrixXd E(3, 3), F(3, 3);
  E << 1, 0, 0, 0, 0, 1, 0, 0, 0;
  F << 0, 1, 0, 0, 1, -1, -1, 0, 0;
  auto w = ldae::numeric::wongSequences(E, F);
  Eigen::Vector3d shift(c, 0, 0);
  Eigen::Vector3d p =
      ldae::numeric::projectAlong(w, Eigen::Vector3d(a, b, c3) - shift) + shift;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(r.rows[0][i + 1], p(i), 1e-10);
}

TEST(ConsistentInit, IndexThreeSolvesHiddenConstraintsAlongT) {
  // At rest at 0.5 rad with x and vx fixed: T ∩ {x, vx held} = span(e_lam),
  // and the hidden constraint of the second derivative gives
  // lam = -g y = g cos(0.5); nothing else moves.
  ldae_model m = handmodels::rawPendulum(0.5);
  const double y0[] = {std::sin(0.5), -std::cos(0.5), 0, 0};
  std::ostringstream log;
  SimResult r = initOnly(m, log);
  ASSERT_EQ(r.status, 0) << r.failure;
  EXPECT_NE(log.str().find("jump space T (dimension 1, index 3)"),
            std::string::npos)
      << log.str();
  EXPECT_EQ(log.str().find("nearest point"), std::string::npos) << log.str();
  EXPECT_NEAR(r.rows[0][5], 9.81 * std::cos(0.5), 1e-7);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(r.rows[0][i + 1], y0[i], 1e-12) << m.var_names[i];
}
