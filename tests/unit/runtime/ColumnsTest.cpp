// The columns of a run (Columns.h): the default choice (outputs but the
// derivatives, then the parameters), kinds, units, descriptions, aliases
// mapped to result columns, parameters with the run's values.
#include "HandModels.h"
#include "ldae/Simulation.h"

#include <gtest/gtest.h>

namespace ldae::runtime {
namespace {

// Outputs of the RC circuit: v, der(v), i, w = -v (an alias), n (a
// constant).
int outputs(double, const double *y, const double *yp, const double *,
            double *out) {
  out[0] = y[0];
  out[1] = yp[0];
  out[2] = y[1];
  out[3] = -y[0];
  out[4] = 7;
  return 0;
}

ldae_model described() {
  static const char *names[] = {"C.v", "der(C.v)", "R.i", "w", "n"};
  static const char *units[] = {"V", "", "A", "V", ""};
  static const char *descs[] = {"voltage", "", "current", "minus voltage",
                                "count"};
  static const int alias[] = {0, 0, 0, -1, 0};
  static const char *punits[] = {"Ohm", "F", "V"};
  static const char *pdescs[] = {"resistance", "capacitance", ""};
  ldae_model m = handmodels::rcCircuit();
  m.n_outputs = 5;
  m.output_names = names;
  m.outputs = outputs;
  m.output_unit = units;
  m.output_description = descs;
  m.output_alias = alias;
  m.param_unit = punits;
  m.param_description = pdescs;
  return m;
}

SimOptions quick() {
  SimOptions o;
  o.stop = 1;
  o.interval = 0.5;
  o.progress = false;
  return o;
}

TEST(Columns, DefaultIsOutputsButDerivativesThenParameters) {
  ldae_model m = described();
  SimOptions o = quick();
  o.params["R"] = 500;
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->model, "RC");
  EXPECT_EQ(r->columns, (std::vector<std::string>{"time", "C.v", "R.i", "w",
                                                  "n", "R", "C", "V0"}));
  ASSERT_EQ(r->info.size(), r->columns.size());
  EXPECT_EQ(r->info[0].kind, ColumnKind::Time);
  EXPECT_EQ(r->info[1].unit, "V");
  EXPECT_EQ(r->info[1].description, "voltage");
  EXPECT_EQ(r->info[1].kind, ColumnKind::Continuous);
  // w = -C.v: minus result column 1.
  EXPECT_EQ(r->info[3].alias, -2);
  EXPECT_EQ(r->info[5].kind, ColumnKind::Parameter);
  EXPECT_EQ(r->info[5].unit, "Ohm");
  EXPECT_EQ(r->info[5].description, "resistance");
  for (const auto &row : r->rows) {
    EXPECT_EQ(row[3], -row[1]);
    EXPECT_EQ(row[5], 500); // the run's value of R
  }
  ASSERT_EQ(r->params.size(), 3u);
  EXPECT_EQ(r->params[0].name, "R");
  EXPECT_EQ(r->params[0].value, 500);
  EXPECT_EQ(r->params[1].unit, "F");
}

TEST(Columns, SelectedByNameWithAliasTargetLeftOut) {
  ldae_model m = described();
  SimOptions o = quick();
  o.outputs = {"w", "der(C.v)", "C"};
  auto r = simulate(m, o);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->columns,
            (std::vector<std::string>{"time", "w", "der(C.v)", "C"}));
  EXPECT_EQ(r->info[1].alias, 0); // C.v is not reported: w is its own
  EXPECT_EQ(r->info[2].kind, ColumnKind::Derivative);
  EXPECT_EQ(r->info[3].kind, ColumnKind::Parameter);
  for (const auto &row : r->rows)
    EXPECT_EQ(row[3], 1e-3);
}

} // namespace
} // namespace ldae::runtime
