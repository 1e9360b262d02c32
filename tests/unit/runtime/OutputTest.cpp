// CSV format, every-step output, the KLU path, and gnuplot pictures.
#include "HandModels.h"
#include "Plot.h"
#include "ResultWriter.h"
#include "Simulator.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <unistd.h>

using namespace ldae::runtime;

TEST(Output, CsvHasHeaderAndSeventeenDigits) {
  SimResult r;
  r.columns = {"time", "x", "m[2].s"};
  r.rows = {{0, 0.1, -1e-300}, {1, 1.0 / 3, 2.5}};
  std::ostringstream out;
  writeCsv(r, out);
  EXPECT_EQ(out.str(), "time,x,m[2].s\n"
                       "0,0.10000000000000001,-1e-300\n"
                       "1,0.33333333333333331,2.5\n");
}

TEST(Output, CloseNames) {
  std::vector<std::string> names{"r1.v", "r1.i", "r2.v", "c.v"};
  auto close = closeNames(names, "r1.w");
  ASSERT_GE(close.size(), 2u);
  EXPECT_EQ(close[0], "r1.v");
  auto sel = selectColumns(names, {"c.v", "r1.i"});
  ASSERT_TRUE(sel);
  EXPECT_EQ(*sel, (std::vector<int>{3, 1}));
}

TEST(Output, EveryStepReportsEachStep) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.stop = 1;
  o.everyStep = true;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 0);
  EXPECT_EQ(long(r->rows.size()), r->stats.steps + 1);
  EXPECT_DOUBLE_EQ(r->rows.back()[0], 1.0);
  for (size_t i = 1; i < r->rows.size(); ++i)
    EXPECT_GT(r->rows[i][0], r->rows[i - 1][0]);
}

TEST(Output, LargeModelUsesKlu) {
  ldae_model m = handmodels::decayChain(20); // 40 unknowns > 32
  SimOptions o;
  o.stop = 2;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->status, 0) << r->failure;
  EXPECT_TRUE(r->stats.sparse);
  EXPECT_EQ(r->stats.n, 40);
  const auto &last = r->rows.back();
  for (int i = 0; i < 20; ++i)
    EXPECT_NEAR(last[1 + 2 * i], std::exp(-0.1 * (i + 1) * 2.0), 1e-6);
}

TEST(Output, PlotsSvgAndPng) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.stop = 1;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r);
  // In the test's working directory (the build tree), never the system
  // temporary directory; removed however the test ends.
  struct ScratchDir {
    std::filesystem::path path =
        std::filesystem::current_path() /
        ("ldae_plot_test_" + std::to_string(::getpid()));
    ScratchDir() { std::filesystem::create_directories(path); }
    ~ScratchDir() { std::filesystem::remove_all(path); }
  } scratch;
  const std::filesystem::path &dir = scratch.path;
  std::string svg = (dir / "rc.svg").string(), png = (dir / "rc.png").string();
  auto ok = plot(*r, svg, {"C.v"});
  ASSERT_TRUE(ok) << ok.error();
  std::ifstream f(svg);
  std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("C.v"), std::string::npos);
  ASSERT_TRUE(plot(*r, png));
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  auto bad = plot(*r, (dir / "rc.pdf").string());
  EXPECT_FALSE(bad);
  auto unknown = plot(*r, svg, {"nope"});
  EXPECT_FALSE(unknown);
}
