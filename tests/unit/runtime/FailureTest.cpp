// The failure path: a residual leaving its domain mid-run gives status 3, a
// message with the time and the equation, and the results so far.
#include "HandModels.h"
#include "ResultWriter.h"
#include "Simulator.h"

#include <gtest/gtest.h>
#include <regex>
#include <sstream>

using namespace ldae::runtime;

TEST(Failure, DomainErrorNamesTimeAndEquation) {
  ldae_model m = handmodels::logDomain();
  SimOptions o;
  o.stop = 2;
  o.interval = 0.01;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  // The log's argument reaches 0 at t = 1: the run fails there.
  std::smatch at;
  ASSERT_TRUE(std::regex_search(r->failure, at,
                                std::regex("simulation failed at t = (\\S+):")))
      << r->failure;
  EXPECT_NEAR(std::stod(at[1]), 1.0, 0.01);
  EXPECT_NE(r->failure.find("equation 2 at domain.lsd:4"), std::string::npos)
      << r->failure;
  EXPECT_NE(r->failure.find("hint: "), std::string::npos);
  // Rows up to the failure are kept: the grid up to t = 1 at most.
  ASSERT_GE(r->rows.size(), 90u);
  double last = r->rows.back()[0];
  EXPECT_GT(last, 0.9);
  EXPECT_LE(last, 1.0);
  EXPECT_NEAR(r->rows.back()[1], 1 - last, 1e-5);
  std::ostringstream csv;
  writeCsv(*r, csv);
  EXPECT_EQ(csv.str().substr(0, 8), "time,y,z");
}
