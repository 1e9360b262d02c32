// The run loop's event handling (docs/events.md) on hand-written models
// with events (EventModels.h), each against its closed form.
#include "EventModels.h"
#include "TestUtil.h"
#include "ldae/Simulation.h"

#include <cmath>
#include <gtest/gtest.h>
#include <sstream>

using namespace ldae::runtime;

namespace {

SimOptions quiet(double stop, double rtol) {
  SimOptions o;
  o.stop = stop;
  o.rtol = rtol;
  o.atol = rtol;
  o.progress = false;
  return o;
}

/// Times of the pairs of rows at one time where column `c` jumps from
/// below `below` ... to above it (a row just before and just after an
/// event).
std::vector<double> eventTimes(const SimResult &r, int c,
                               bool (*jump)(double before, double after)) {
  std::vector<double> times;
  for (size_t i = 1; i < r.rows.size(); ++i)
    if (r.rows[i][0] == r.rows[i - 1][0] &&
        jump(r.rows[i - 1][c], r.rows[i][c]))
      times.push_back(r.rows[i][0]);
  return times;
}

} // namespace

// h'' = -g from h = 1 at rest, e = 0.8: the impact speeds are u e^k, the
// flights 2 u e^k / g.
TEST(Events, BouncingBallMatchesTheClosedForm) {
  const double g = 9.81, e = 0.8;
  const double t1 = std::sqrt(2 / g), u = g * t1;
  std::vector<double> bounce{t1}, apexTime, apexHeight;
  for (int k = 1; k < 10; ++k) {
    double w = u * std::pow(e, k);
    apexTime.push_back(bounce.back() + w / g);
    apexHeight.push_back(w * w / (2 * g));
    bounce.push_back(bounce.back() + 2 * w / g);
  }
  ldae_model m = handmodels::bouncingBall(e);
  SimOptions o = quiet(3.62, 1e-11);
  o.times = apexTime;
  o.times.push_back(3.62);
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  int h = testutil::column(*r, "h"), v = testutil::column(*r, "v");
  std::vector<double> seen =
      eventTimes(*r, v, [](double a, double b) { return a < 0 && b > 0; });
  ASSERT_EQ(seen.size(), bounce.size());
  for (size_t k = 0; k < bounce.size(); ++k)
    EXPECT_NEAR(seen[k], bounce[k], 1e-8) << "bounce " << k + 1;
  for (size_t k = 0; k < apexTime.size(); ++k) {
    auto row = std::find_if(r->rows.begin(), r->rows.end(),
                            [&](auto &x) { return x[0] == apexTime[k]; });
    ASSERT_NE(row, r->rows.end());
    EXPECT_NEAR((*row)[h], apexHeight[k], 1e-8) << "apex " << k + 1;
  }
  EXPECT_EQ(r->stats.events, 10); // h <= 0 crossing back shows nowhere
  EXPECT_EQ(r->stats.jumps, 10);
  EXPECT_EQ(r->stats.timeEvents, 0);
  EXPECT_EQ(r->rows.back()[0], 3.62);
}

// Past the accumulation point t* = t1 (1 + 2 e / (1 - e)) the ball is at
// rest: the run ends cleanly at the stop time and says so.
TEST(Events, BouncingBallPastTheAccumulationPointRests) {
  const double g = 9.81, e = 0.8, t1 = std::sqrt(2 / g);
  const double tStar = t1 * (1 + 2 * e / (1 - e));
  ldae_model m = handmodels::bouncingBall(e);
  SimOptions o = quiet(10, 1e-8);
  std::ostringstream log;
  o.log = &log;
  o.interval = 0.5;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_NE(log.str().find("events accumulate (Zeno)"), std::string::npos)
      << log.str();
  int h = testutil::column(*r, "h"), v = testutil::column(*r, "v");
  EXPECT_EQ(r->rows.back()[0], 10.0);
  EXPECT_NEAR(r->rows.back()[h], 0, 1e-6);
  EXPECT_EQ(r->rows.back()[v], 0);
  // The rest starts close to t* (the last bounces are below the
  // tolerances), every row after t* is at rest, and the ball never went
  // through the floor.
  auto rest = std::find_if(r->rows.begin(), r->rows.end(), [&](auto &row) {
    return row[0] > 1 && row[v] == 0;
  });
  ASSERT_NE(rest, r->rows.end());
  EXPECT_NEAR((*rest)[0], tStar, 1e-2);
  for (const auto &row : r->rows) {
    EXPECT_GT(row[h], -1e-6) << "t = " << row[0];
    if (row[0] > tStar + 1e-6) {
      EXPECT_EQ(row[v], 0) << "t = " << row[0];
    }
  }
  EXPECT_GT(r->stats.events, 30);
}

// count goes up at 0.1, 0.2, ..., 1.0 (the stop time included); x is the
// integral of the staircase.
TEST(Events, SampledCounter) {
  ldae_model m = handmodels::sampledCounter();
  SimOptions o = quiet(1, 1e-10);
  o.interval = 0.05;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  int x = testutil::column(*r, "x"), count = testutil::column(*r, "count");
  EXPECT_EQ(r->stats.timeEvents, 10);
  EXPECT_EQ(r->stats.events, 10);
  for (const auto &row : r->rows) {
    double t = row[0];
    // Between instants, count = floor(t / 0.1); at an instant the rows
    // before and after show both values.
    if (std::fabs(t / 0.1 - std::round(t / 0.1)) > 1e-9) {
      EXPECT_EQ(row[count], std::floor(t / 0.1)) << "t = " << t;
      double k = std::floor(t / 0.1);
      EXPECT_NEAR(row[x], 0.1 * k * (k - 1) / 2 + k * (t - 0.1 * k), 1e-9)
          << "t = " << t;
    }
  }
  // The last rows: before and after the instant at the stop time.
  ASSERT_GE(r->rows.size(), 2u);
  EXPECT_EQ(r->rows.back()[0], 1.0);
  EXPECT_EQ(r->rows.back()[count], 10);
  EXPECT_NEAR(r->rows.back()[x], 4.5, 1e-9);
  EXPECT_EQ(r->rows[r->rows.size() - 2][count], 9);
}

// A time event is a stop time of the integrator: it is hit exactly, with
// the rows just before and just after it at that very time.
TEST(Events, TimeEventAtExactlyItsThreshold) {
  const double t0 = 0.3 + 1e-9; // off the output grid
  ldae_model m = handmodels::timeThreshold(t0);
  SimOptions o = quiet(1, 1e-10);
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  int x = testutil::column(*r, "x");
  size_t at = 0;
  for (size_t i = 0; i < r->rows.size(); ++i)
    if (r->rows[i][0] == t0)
      ++at;
  EXPECT_EQ(at, 2u);
  EXPECT_EQ(r->stats.timeEvents, 1);
  for (const auto &row : r->rows)
    EXPECT_NEAR(row[x], std::max(0.0, row[0] - t0), 1e-12) << row[0];
  EXPECT_EQ(r->rows.back()[0], 1.0);
}

// The threshold at the start time: the initial event sees time >= t0.
TEST(Events, TimeRelationTrueAtTheStart) {
  ldae_model m = handmodels::timeThreshold(0.0);
  auto r = simulate(m, quiet(1, 1e-10));
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_NEAR(r->rows.back()[1], 1.0, 1e-12);
  EXPECT_EQ(r->stats.events, 0);
}

// heat switches off at T = 0.8 and on at T = 0.2: T is a triangle wave
// 0.5 -> 0.8 (t = 0.3) -> 0.2 (0.9) -> 0.8 (1.5) ...
TEST(Events, HysteresisRelay) {
  ldae_model m = handmodels::hysteresis();
  SimOptions o = quiet(4, 1e-10);
  o.interval = 0.01;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  int T = testutil::column(*r, "T"), heat = testutil::column(*r, "heat");
  auto exact = [](double t) {
    if (t <= 0.3)
      return 0.5 + t;
    double s = std::fmod(t - 0.3, 1.2);
    return s <= 0.6 ? 0.8 - s : 0.2 + (s - 0.6);
  };
  for (const auto &row : r->rows)
    EXPECT_NEAR(row[T], exact(row[0]), 1e-8) << "t = " << row[0];
  std::vector<double> off =
      eventTimes(*r, heat, [](double a, double b) { return a == 1 && b == 0; });
  std::vector<double> on =
      eventTimes(*r, heat, [](double a, double b) { return a == 0 && b == 1; });
  ASSERT_EQ(off.size(), 4u); // 0.3, 1.5, 2.7, 3.9
  ASSERT_EQ(on.size(), 3u);  // 0.9, 2.1, 3.3
  for (size_t k = 0; k < off.size(); ++k)
    EXPECT_NEAR(off[k], 0.3 + 1.2 * double(k), 1e-8);
  for (size_t k = 0; k < on.size(); ++k)
    EXPECT_NEAR(on[k], 0.9 + 1.2 * double(k), 1e-8);
}

// From t = 1 on the when-clauses switch s at every crossing of x = 0:
// chattering, reported with the conditions; the rows up to it are kept.
TEST(Events, TogglingWhenIsReportedAsChattering) {
  ldae_model m = handmodels::togglingWhen();
  SimOptions o = quiet(2, 1e-8);
  o.interval = 0.1;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  EXPECT_NE(r->failure.find("chattering at t = 1"), std::string::npos)
      << r->failure;
  EXPECT_NE(r->failure.find("(x <= 0)"), std::string::npos) << r->failure;
  EXPECT_NE(r->failure.find("(x > 0)"), std::string::npos) << r->failure;
  ASSERT_GE(r->rows.size(), 11u);
  EXPECT_NEAR(r->rows.back()[0], 1.0, 1e-7);
  EXPECT_NEAR(r->rows[10][0], 1.0, 1e-12);
}

// An event 1e-13 before the stop time: the last row is still the stop
// time's.
TEST(Events, EventNearTheStopTimeKeepsTheLastRow) {
  const double c = 1 - 1e-13;
  ldae_model m = handmodels::resetNear(c);
  SimOptions o = quiet(1, 1e-10);
  o.interval = 0.1;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_EQ(r->stats.events, 1);
  EXPECT_EQ(r->rows.back()[0], 1.0);
  EXPECT_NEAR(r->rows.back()[1], 1 - c, 1e-12);
  // 11 grid rows and the two of the event.
  EXPECT_EQ(r->rows.size(), 13u);
}

// terminate() ends the run at its event with status 0.
TEST(Events, TerminateEndsTheRun) {
  ldae_model m = handmodels::stopper(true);
  SimOptions o = quiet(1, 1e-10);
  std::ostringstream log;
  o.log = &log;
  o.interval = 0.1;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_NEAR(r->rows.back()[0], 0.5, 1e-9);
  EXPECT_NE(log.str().find("terminate: x reached 0.5"), std::string::npos)
      << log.str();
  // The warning-level assert (x < 0.3) once on the log.
  std::string text = log.str();
  size_t first = text.find("warning: assertion failed");
  ASSERT_NE(first, std::string::npos) << text;
  EXPECT_EQ(text.find("warning: assertion failed", first + 1),
            std::string::npos);
}

// An error-level assert stops the run (status 3) with its message and
// origin at the first output row that breaks it.
TEST(Events, AssertOfLevelErrorStopsTheRun) {
  ldae_model m = handmodels::stopper(false);
  SimOptions o = quiet(1, 1e-10);
  o.interval = 0.1;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  EXPECT_EQ(r->failure, "assertion failed at t = 0.7: x stays below the "
                        "limit (assert at stopper.lsd:7:3)");
  EXPECT_NEAR(r->rows.back()[0], 0.7, 1e-12);
}

// A mode change asks the provider for the new mode's model and carries x
// over by name: x = t up to 1, then exp(-(t - 1)).
TEST(Events, ModeChangeContinuesWithTheNewModel) {
  static ldae_model modes[2] = {handmodels::switchedMode(0),
                                handmodels::switchedMode(1)};
  SimOptions o = quiet(2, 1e-10);
  o.interval = 0.25;
  std::vector<std::vector<double>> asked;
  o.modeProvider = [&](const std::vector<double> &values)
      -> ldae::Expected<const ldae_model *> {
    asked.push_back(values);
    return &modes[values[0] != 0];
  };
  auto r = simulate(modes[0], o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  ASSERT_EQ(asked, (std::vector<std::vector<double>>{{1}}));
  EXPECT_EQ(r->stats.modeSwitches, 1);
  EXPECT_EQ(r->stats.events, 1);
  for (size_t i = 0; i < r->rows.size(); ++i) {
    double t = r->rows[i][0];
    bool after =
        t > 1 || (t == 1 && i + 1 < r->rows.size() && r->rows[i + 1][0] > 1);
    EXPECT_NEAR(r->rows[i][1], after ? std::exp(-(t - 1)) : t, 1e-8)
        << "t = " << t;
  }
  EXPECT_EQ(r->rows.back()[0], 2.0);

  // Without a provider the run ends at the change, naming it.
  o.modeProvider = nullptr;
  r = simulate(modes[0], o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  EXPECT_EQ(r->failure, "t = 1: the mode changed ('time >= 1' = 1) and the "
                        "run has no model of the new mode (no mode provider)");
}
