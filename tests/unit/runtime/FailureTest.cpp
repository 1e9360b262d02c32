// The failure path: a residual leaving its domain mid-run gives status 3, a
// message with the time and the equation, and the results so far.
#include "HandModels.h"
#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"

#include <gtest/gtest.h>
#include <regex>
#include <sstream>

using namespace ldae::runtime;

namespace {
/// Runs `m` to t = 2 and checks that it failed near t = 1 in `equation`
/// (any equation or none when empty).
SimResult failNearOne(const ldae_model &m, const std::string &equation) {
  SimOptions o;
  o.stop = 2;
  o.interval = 0.01;
  o.progress = false;
  auto r = simulate(m, o);
  EXPECT_TRUE(r) << (r ? "" : r.error());
  if (!r)
    return SimResult{};
  EXPECT_EQ(r->status, 3);
  std::smatch at;
  EXPECT_TRUE(std::regex_search(r->failure, at,
                                std::regex("simulation failed at t = (\\S+):")))
      << r->failure;
  if (at.size() > 1) {
    EXPECT_NEAR(std::stod(at[1]), 1.0, 0.01);
  }
  if (!equation.empty()) {
    EXPECT_NE(r->failure.find("in " + equation), std::string::npos)
        << r->failure;
  }
  EXPECT_NE(r->failure.find("hint: "), std::string::npos);
  EXPECT_LE(r->rows.back()[0], 1.0);
  return *r;
}
} // namespace

TEST(Failure, DomainErrorNamesTimeAndEquation) {
  // The log's argument reaches 0 at t = 1: the run fails there.
  SimResult res =
      failNearOne(handmodels::logDomain(), "equation 2 at domain.lsd:4");
  const SimResult *r = &res;
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

namespace {
// y' = 1, 0 = z^2 + y - 1: z = sqrt(1 - y) meets a singular Jacobian (2 z)
// at t = 1 and has no real solution after it.
int foldRes(double, const double *y, const double *yp, const double *,
            double *r) {
  r[0] = yp[0] - 1;
  r[1] = y[1] * y[1] + y[0] - 1;
  return 0;
}
int foldJac(double, const double *y, const double *, const double *, double cj,
            double *J) {
  J[0] = cj;
  J[1] = 1;
  J[2] = 0;
  J[3] = 2 * y[1];
  return 0;
}
} // namespace

TEST(Failure, SingularIterationMatrixNamesEquationAndHint) {
  static const char *names[] = {"y", "z"};
  static const char *origin[] = {"fold.lsd:3", "fold.lsd:4"};
  static const double y0[] = {0, 1}, yp0[] = {1, 0}, nominal[] = {1, 1};
  static const int fixed[] = {1, 0}, diff[] = {1, 0};
  static ldae_state_set set{};
  set.is_differential = diff;
  set.residual = foldRes;
  set.jacobian_dense = foldJac;
  ldae_model m =
      handmodels::makeModel("Fold", 2, names, y0, yp0, nominal, fixed, &set);
  m.residual_origin = origin;
  m.algebraic_error_test = 1; // index 1: a fold, not a high index
  SimResult r = failNearOne(m, "equation 2 at fold.lsd:4");
  EXPECT_NE(r.failure.find("largest local errors: 'z'"), std::string::npos)
      << r.failure;
  // A fold of an index-1 system: the hint does not send to --method dd.
  EXPECT_NE(r.failure.find("hint: check the start values; tighten or "
                           "loosen --rtol and --atol"),
            std::string::npos)
      << r.failure;
  EXPECT_EQ(r.failure.find("--method dd"), std::string::npos) << r.failure;
}

namespace {
// The fold in block 0 of a 40-unknown model (KLU, the sparse failure
// report's path); blocks i > 0: y_i' = -y_i, 0 = z_i - y_i.
constexpr int kFoldBlocks = 20;
int bigFoldRes(double t, const double *y, const double *yp, const double *p,
               double *r) {
  foldRes(t, y, yp, p, r);
  for (int i = 1; i < kFoldBlocks; ++i) {
    r[2 * i] = yp[2 * i] + y[2 * i];
    r[2 * i + 1] = y[2 * i + 1] - y[2 * i];
  }
  return 0;
}
// Columns (y_i, z_i) with rows {2i, 2i+1} each.
int bigFoldJac(double, const double *y, const double *, const double *,
               double cj, double *v) {
  v[0] = cj;
  v[1] = 1;
  v[2] = 0;
  v[3] = 2 * y[1];
  for (int i = 1; i < kFoldBlocks; ++i) {
    v[4 * i + 0] = cj + 1;
    v[4 * i + 1] = -1;
    v[4 * i + 2] = 0;
    v[4 * i + 3] = 1;
  }
  return 0;
}
} // namespace

TEST(Failure, SparseSingularIterationMatrixNamesEquation) {
  constexpr int n = 2 * kFoldBlocks;
  static double y0[n], yp0[n], nominal[n];
  static int fixed[n], diff[n], colptr[n + 1], rowind[2 * n];
  for (int i = 0; i < kFoldBlocks; ++i) {
    y0[2 * i] = i == 0 ? 0 : 1;
    y0[2 * i + 1] = 1;
    yp0[2 * i] = i == 0 ? 1 : -1;
    yp0[2 * i + 1] = 0;
    diff[2 * i] = fixed[2 * i] = 1;
    diff[2 * i + 1] = fixed[2 * i + 1] = 0;
    for (int c : {2 * i, 2 * i + 1}) {
      rowind[2 * c] = 2 * i;
      rowind[2 * c + 1] = 2 * i + 1;
    }
  }
  for (int c = 0; c <= n; ++c)
    colptr[c] = 2 * c;
  for (double &d : nominal)
    d = 1;
  static ldae_state_set set{};
  set.is_differential = diff;
  set.residual = bigFoldRes;
  set.jacobian_csc = bigFoldJac;
  set.jac_nnz = 2 * n;
  set.jac_colptr = colptr;
  set.jac_rowind = rowind;
  ldae_model m = handmodels::makeModel("BigFold", n, nullptr, y0, yp0, nominal,
                                       fixed, &set);
  SimResult r = failNearOne(m, "");
  EXPECT_TRUE(r.stats.sparse);
  // IDA may step past the fold before giving up (then the matrix is not
  // singular and no equation is named); an equation named is the fold's.
  size_t named = r.failure.find("\n  in equation ");
  if (named != std::string::npos) {
    EXPECT_EQ(r.failure.substr(named, 17), "\n  in equation 2\n") << r.failure;
  }
}

// A SUNDIALS call that rejects its input once the options were accepted
// (here IDASVtolerances: a negative nominal value makes an absolute
// tolerance negative) is a numerical failure of the run, status 3 with the
// time and a hint, never an Error (which the driver reports as a bad
// command line, exit 2).
TEST(Failure, SolverSetUpErrorIsStatusThree) {
  ldae_model m = handmodels::robertson();
  static const double negative[] = {1, -100, 100};
  m.nominal = negative;
  SimOptions o;
  o.stop = 1;
  o.progress = false;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->status, 3);
  EXPECT_EQ(r->failure.rfind("simulation failed at t = 0: internal error: "
                             "IDASVtolerances",
                             0),
            0u)
      << r->failure;
  EXPECT_NE(r->failure.find("\n  hint: the solver could not be set up here"),
            std::string::npos)
      << r->failure;
  EXPECT_EQ(r->columns, (std::vector<std::string>{"time", "y1", "y2", "y3"}));
  EXPECT_TRUE(r->rows.empty());
}
