// The integrator choice and CVODE on a hand-written explicit ODE against
// its closed form: x' = -a x, y' = a x - b y, x(0) = 1, y(0) = 0, so
// x = exp(-a t), y = a/(b - a) (exp(-a t) - exp(-b t)). A root at
// x = 1/2 (t = ln 2 / a) is found by either solver.
#include "HandModels.h"
#include "TestUtil.h"
#include "ldae/Simulation.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace ldae::runtime;

namespace {

constexpr double kA = 2.0, kB = 0.5;

// Row i is y'[i] - f_i(y): the explicit ODE form.
int res(double, const double *y, const double *yp, const double *, double *r) {
  r[0] = yp[0] + kA * y[0];
  r[1] = yp[1] - kA * y[0] + kB * y[1];
  return 0;
}
int jac(double, const double *, const double *, const double *, double cj,
        double *J) {
  J[0] = kA + cj; // (0,0)
  J[1] = -kA;     // (1,0)
  J[2] = 0;       // (0,1)
  J[3] = kB + cj; // (1,1)
  return 0;
}
int roots(double, const double *y, const double *, const double *, double *g) {
  g[0] = y[0] - 0.5;
  return 0;
}

const char *const kNames[] = {"x", "y"};
const double kY0[] = {1, 0}, kYp0[] = {-kA, kA}, kNominal[] = {1, 1};
const int kFixed[] = {1, 1}, kDiff[] = {1, 1};

ldae_model chain(bool explicitOde) {
  static ldae_state_set set{};
  set.is_differential = kDiff;
  set.residual = res;
  set.jacobian_dense = jac;
  set.description = "states: x, y";
  ldae_model m = handmodels::makeModel("Chain", 2, kNames, kY0, kYp0,
                                       kNominal, kFixed, &set);
  m.n_roots = 1;
  m.roots = roots;
  m.explicit_ode = explicitOde ? 1 : 0;
  m.algebraic_error_test = 1;
  return m;
}

SimOptions options(double interval, double rtol, IntegratorChoice choice) {
  SimOptions o;
  o.stop = 3;
  o.interval = interval;
  o.rtol = rtol;
  o.atol = rtol / 100;
  o.progress = false;
  o.integrator = choice;
  return o;
}

SimResult run(const ldae_model &m, IntegratorChoice choice) {
  auto r = simulate(m, options(0.1, 1e-9, choice));
  EXPECT_TRUE(r) << (r ? "" : r.error());
  if (!r)
    return {};
  EXPECT_EQ(r->status, 0) << r->failure;
  return *r;
}

double worstError(const SimResult &r) {
  double worst = 0;
  for (const auto &row : r.rows) {
    double t = row[0];
    double x = std::exp(-kA * t);
    double y = kA / (kB - kA) * (std::exp(-kA * t) - std::exp(-kB * t));
    worst = std::max({worst, std::fabs(row[1] - x), std::fabs(row[2] - y)});
  }
  return worst;
}

} // namespace

TEST(Integrator, AutoRunsCvodeBdfForAnExplicitOde) {
  SimResult r = run(chain(true), IntegratorChoice::Auto);
  EXPECT_EQ(r.stats.integrator, "CVODE (BDF)");
  ASSERT_EQ(r.rows.size(), 31u);
  EXPECT_LE(worstError(r), 1e-8);
  EXPECT_EQ(r.stats.rootsFound, 1);
}

TEST(Integrator, AutoRunsIdaWithoutTheOdeMark) {
  SimResult r = run(chain(false), IntegratorChoice::Auto);
  EXPECT_EQ(r.stats.integrator, "IDA");
  EXPECT_LE(worstError(r), 1e-8);
  EXPECT_EQ(r.stats.rootsFound, 1);
}

TEST(Integrator, EveryChoiceMatchesTheClosedForm) {
  for (auto [choice, name] :
       {std::pair{IntegratorChoice::Ida, "IDA"},
        {IntegratorChoice::CvodeBdf, "CVODE (BDF)"},
        {IntegratorChoice::CvodeAdams, "CVODE (Adams)"}}) {
    SimResult r = run(chain(true), choice);
    EXPECT_EQ(r.stats.integrator, name);
    EXPECT_LE(worstError(r), 1e-8) << name;
  }
}

TEST(Integrator, CvodeRefusesADae) {
  ldae_model m = handmodels::rcCircuit();
  SimOptions o;
  o.progress = false;
  o.integrator = IntegratorChoice::CvodeBdf;
  auto r = simulate(m, o);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("CVODE integrates explicit ODEs only"),
            std::string::npos)
      << r.error();
}

// Output times the integrator steps over are interpolated: far fewer steps
// than rows on a slow solution, each row still on the closed form.
TEST(Integrator, InterpolatesOutputTimes) {
  auto r = simulate(chain(true), options(0.001, 1e-6, IntegratorChoice::Auto));
  ASSERT_TRUE(r) << r.error();
  ASSERT_EQ(r->rows.size(), 3001u);
  EXPECT_LT(r->stats.steps, 300);
  EXPECT_LE(worstError(*r), 1e-5);
}
