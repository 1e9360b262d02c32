// CSV format, every-step output, the KLU path, and gnuplot pictures.
#include "HandModels.h"
#include "ldae/Plot.h"
#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <unistd.h>

using namespace ldae::runtime;

// The shortest text that reads back to the same double, for every value,
// the extremes and non-finite ones included.
TEST(Output, CsvHasHeaderAndShortestRoundTripNumbers) {
  SimResult r;
  r.columns = {"time", "x", "m[2].s"};
  r.rows = {{0, 0.1, -1e-300}, {1, 1.0 / 3, 2.5}};
  std::ostringstream out;
  writeCsv(r, out);
  EXPECT_EQ(out.str(), "time,x,m[2].s\n"
                       "0,0.1,-1e-300\n"
                       "1,0.3333333333333333,2.5\n");
  const double values[] = {0.1 + 0.2, 1e22, 5e-324, -2.2250738585072014e-308,
                           1.7976931348623157e308, 123456789012345680.0,
                           std::nextafter(1.0, 2.0)};
  for (double v : values)
    EXPECT_EQ(std::strtod(formatValue(v).c_str(), nullptr), v) << formatValue(v);
  EXPECT_EQ(formatValue(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(formatValue(INFINITY), "inf");
  EXPECT_EQ(formatValue(-INFINITY), "-inf");
  EXPECT_EQ(formatValue(NAN), "nan");
}

// Rows longer than the writer's block go out whole and in order.
TEST(Output, CsvOfManyRowsReadsBack) {
  SimResult r;
  r.columns = {"time", "x"};
  for (int i = 0; i < 200000; ++i)
    r.rows.push_back({i * 0.001, std::sin(i * 0.001) / 3});
  std::ostringstream out;
  writeCsv(r, out);
  std::istringstream in(out.str());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time,x");
  for (const auto &row : r.rows) {
    ASSERT_TRUE(std::getline(in, line));
    size_t comma = line.find(',');
    ASSERT_NE(comma, std::string::npos);
    EXPECT_EQ(std::strtod(line.substr(0, comma).c_str(), nullptr), row[0]);
    EXPECT_EQ(std::strtod(line.c_str() + comma + 1, nullptr), row[1]);
  }
  EXPECT_FALSE(std::getline(in, line));
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
  auto bad = plot(*r, (dir / "rc.jpg").string());
  EXPECT_FALSE(bad);
  auto unknown = plot(*r, svg, {"nope"});
  EXPECT_FALSE(unknown);
}
