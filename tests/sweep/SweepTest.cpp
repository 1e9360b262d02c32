// The command-line sweep: axis parsing, grid order, members that fail, the
// files, and one compiled model simulated from several threads at once.
#include "HandModels.h"
#include "ldae/Sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace ldae;
using namespace ldae::runtime;

TEST(SweepAxis, Range) {
  auto a = parseSweepAxis("R=1:10:100");
  ASSERT_TRUE(a) << a.error();
  EXPECT_EQ(a->name, "R");
  ASSERT_EQ(a->values.size(), 100u);
  EXPECT_EQ(a->values.front(), 1.0);
  EXPECT_EQ(a->values.back(), 10.0);
  EXPECT_DOUBLE_EQ(a->values[11], 2.0); // 1 + 9 * 11 / 99
  auto down = parseSweepAxis(" c.C = 2e-3 : 1e-3 : 3 ");
  ASSERT_TRUE(down) << down.error();
  EXPECT_EQ(down->name, "c.C");
  EXPECT_EQ(down->values, (std::vector<double>{2e-3, 1.5e-3, 1e-3}));
}

TEST(SweepAxis, List) {
  auto a = parseSweepAxis("R=1,2,5");
  ASSERT_TRUE(a) << a.error();
  EXPECT_EQ(a->values, (std::vector<double>{1, 2, 5}));
  auto one = parseSweepAxis("k=-0.5");
  ASSERT_TRUE(one);
  EXPECT_EQ(one->values, (std::vector<double>{-0.5}));
  auto signs = parseSweepAxis("k=+1e3, .25");
  ASSERT_TRUE(signs) << signs.error();
  EXPECT_EQ(signs->values, (std::vector<double>{1000, 0.25}));
}

TEST(SweepAxis, Refusals) {
  struct Case {
    const char *spec, *says;
  } cases[] = {
      {"R", "expected name=first:last:count or name=v1,v2,..."},
      {"=1,2", "no parameter name"},
      {"R=1:2", "a range is first:last:count"},
      {"R=1:2:3:4", "a range is first:last:count"},
      {"R=1:x:3", "'x' is not a finite number"},
      {"R=1:2:1", "the count '1' must be an integer from 2"},
      {"R=1:2:2.5", "the count '2.5'"},
      {"R=1:2:", "the count ''"},
      {"R=1,2x", "'2x' is not a finite number"},
      {"R=1e999", "'1e999' is not a finite number"},
      {"R=1,,2", "'' is not a finite number"},
      {"R=1,inf", "'inf' is not a finite number"},
      {"R=", "'' is not a finite number"},
  };
  for (const Case &c : cases) {
    auto a = parseSweepAxis(c.spec);
    ASSERT_FALSE(a) << c.spec;
    EXPECT_NE(a.error().find(c.says), std::string::npos)
        << c.spec << ": " << a.error();
  }
}

TEST(SweepAxis, OneNameOnce) {
  EXPECT_TRUE(checkSweepAxes({{"R", {1}}, {"C", {2}}}));
  auto twice = checkSweepAxes({{"R", {1, 2}}, {"C", {1}}, {"R", {3}}});
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error(),
            "'R' is swept twice (list every value in one --sweep)");
}

TEST(SweepGrid, FirstAxisSlowest) {
  auto m = sweepMembers({{"R", {1, 2}}, {"C", {10, 20, 30}}});
  ASSERT_EQ(m.size(), 6u);
  double expect[6][2] = {{1, 10}, {1, 20}, {1, 30}, {2, 10}, {2, 20}, {2, 30}};
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(m[k].at("R"), expect[k][0]) << k;
    EXPECT_EQ(m[k].at("C"), expect[k][1]) << k;
  }
  EXPECT_TRUE(sweepMembers({}).empty());
  EXPECT_TRUE(sweepMembers({{"R", {1}}, {"C", {}}}).empty());
}

namespace {

/// A stand-in simulation: one row per second up to 2 s of x = R * t and
/// the parameter R, status 3 at R = 3 (rows kept up to t = 1), refused
/// options at R = 4.
Expected<SimResult> fakeSimulate(const SimOptions &o) {
  double R = o.params.at("R");
  if (R == 4)
    return Error{"parameter 'R' is structural"};
  SimResult r;
  r.columns = {"time", "x", "R"}; // results carry the parameters
  for (double t : {0.0, 1.0, 2.0}) {
    r.rows.push_back({t, R * t, R});
    if (R == 3 && t == 1) {
      r.status = 3;
      r.failure = "at t = 1: step size too small\nhint: none";
      break;
    }
  }
  if (o.log)
    *o.log << "initialization: R = " << R
           << "\ninitialization: the start values are consistent\n";
  return r;
}

struct ScratchDir {
  std::filesystem::path path = std::filesystem::current_path() /
                               ("ldae_sweep_test_" + std::to_string(::getpid()));
  ScratchDir() { std::filesystem::create_directories(path); }
  ~ScratchDir() { std::filesystem::remove_all(path); }
};

std::string readFile(const std::filesystem::path &p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

} // namespace

TEST(SweepRun, FailingMembersKeepTheOthers) {
  auto members = sweepMembers({{"R", {1, 2, 3, 4, 5}}});
  SimOptions base;
  std::ostringstream progress, log;
  base.log = &log;
  auto out = runSweep(fakeSimulate, base, members, 3, &progress);
  ASSERT_EQ(out.size(), 5u);
  for (size_t k = 0; k < 5; ++k)
    EXPECT_EQ(out[k].params.at("R"), double(k + 1));
  ASSERT_TRUE(out[0].result);
  EXPECT_EQ(out[0].result->rows.back()[1], 2.0);
  EXPECT_EQ(out[4].result->rows.back()[1], 10.0);
  ASSERT_TRUE(out[2].result);
  EXPECT_EQ(out[2].result->status, 3);
  EXPECT_EQ(out[2].result->rows.size(), 2u);
  ASSERT_FALSE(out[3].result);
  EXPECT_EQ(out[3].result.error(), "parameter 'R' is structural");
  // One progress line per member, in the order they finished.
  std::string p = progress.str();
  EXPECT_EQ(std::count(p.begin(), p.end(), '\n'), 5);
  EXPECT_NE(p.find("member 3 (R=3) failed: at t = 1: step size too small\n"),
            std::string::npos)
      << p;
  EXPECT_NE(p.find("member 4 (R=4) failed: parameter 'R' is structural"),
            std::string::npos);
  EXPECT_NE(p.find(" of 5 done; member 1 (R=1) ok ("), std::string::npos);
  // Each member's log, whole and named; a line another member logged
  // already is not repeated; the rest of a failure's message (its hint).
  std::string l = log.str();
  EXPECT_NE(l.find("member 5: initialization: R = 5\n"), std::string::npos)
      << l;
  size_t consistent = l.find("the start values are consistent\n");
  ASSERT_NE(consistent, std::string::npos) << l;
  EXPECT_EQ(l.find("the start values are consistent", consistent + 1),
            std::string::npos)
      << l;
  EXPECT_NE(l.find("member 3: hint: none\n"), std::string::npos) << l;
}

TEST(SweepRun, EscapingExceptionIsTheMembersError) {
  auto out = runSweep(
      [](const SimOptions &o) -> Expected<SimResult> {
        if (o.params.at("R") == 2)
          throw std::bad_alloc();
        return fakeSimulate(o);
      },
      SimOptions{}, sweepMembers({{"R", {1, 2}}}), 2, nullptr);
  ASSERT_TRUE(out[0].result);
  ASSERT_FALSE(out[1].result);
  EXPECT_NE(out[1].result.error().find("internal error"), std::string::npos);
}

namespace {

/// The fake sweep over `Rs` written to `file` in `dir`; its members.
std::vector<SweepMember> writeFakeSweep(const std::vector<double> &Rs,
                                        const ScratchDir &dir,
                                        const std::string &file,
                                        ResultFormat format) {
  auto out = runSweep(fakeSimulate, SimOptions{}, sweepMembers({{"R", Rs}}),
                      2, nullptr);
  auto w = writeSweep(out, (dir.path / file).string(), format);
  EXPECT_TRUE(w) << w.error();
  return out;
}

} // namespace

TEST(SweepFile, CsvLongTable) {
  ScratchDir dir;
  auto out = writeFakeSweep({1, 3, 4}, dir, "sweep.csv", ResultFormat::Csv);
  // R once, as swept.
  EXPECT_EQ(readFile(dir.path / "sweep.csv"), "member,R,time,x\n"
                           "1,1,0,0\n1,1,1,1\n1,1,2,2\n"
                           "2,3,0,0\n2,3,1,3\n");
  EXPECT_FALSE(writeSweep(out, "-", ResultFormat::Mat));
}

TEST(SweepFile, MatHasEveryMember) {
  ScratchDir dir;
  writeFakeSweep({1, 3, 4}, dir, "sweep.mat", ResultFormat::Mat);
  std::string bytes = readFile(dir.path / "sweep.mat");
  for (const char *name : {"sweep_names", "sweep_values", "status", "failure",
                           "name", "member_1", "member_2", "member_3"})
    EXPECT_NE(bytes.find(std::string(name) + '\0'), std::string::npos)
        << name;
}

TEST(SweepFile, MatWhenEveryMemberRan) {
  // No failure message at all: the `failure` matrix is blank, not absent.
  ScratchDir dir;
  writeFakeSweep({1, 2}, dir, "ok.mat", ResultFormat::Mat);
  EXPECT_NE(readFile(dir.path / "ok.mat").find(std::string("failure") + '\0'),
            std::string::npos);
}

TEST(SweepThreads, OneModelFromSeveralThreads) {
  // v(t) = V0 (1 - exp(-t / (R C))) with C = 1e-3, V0 = 1: every member
  // against its closed form, the members run four at a time.
  ldae_model model = handmodels::rcCircuit();
  SimOptions base;
  base.stop = 2;
  base.rtol = 1e-8;
  base.atol = 1e-10;
  base.progress = false;
  std::vector<double> Rs;
  for (int k = 0; k < 16; ++k)
    Rs.push_back(250 + 125 * k);
  auto out = runSweep(
      [&model](const SimOptions &o) { return simulate(model, o); }, base,
      sweepMembers({{"R", Rs}}), 4, nullptr);
  ASSERT_EQ(out.size(), Rs.size());
  for (size_t k = 0; k < Rs.size(); ++k) {
    ASSERT_TRUE(out[k].result) << out[k].result.error();
    const SimResult &r = *out[k].result;
    ASSERT_EQ(r.status, 0) << r.failure;
    auto v = std::find(r.columns.begin(), r.columns.end(), "C.v");
    ASSERT_NE(v, r.columns.end());
    size_t c = size_t(v - r.columns.begin());
    double tau = Rs[k] * 1e-3;
    for (const std::vector<double> &row : r.rows)
      ASSERT_NEAR(row[c], 1 - std::exp(-row[0] / tau), 1e-6)
          << "R = " << Rs[k] << ", t = " << row[0];
  }
}
