// The panels of a plot (planPlot): grouping by unit, splitting by scale,
// the default curves and the caps. No gnuplot needed.
#include "ldae/Plot.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ldae::runtime;

namespace {

struct Column {
  std::string name;
  ColumnKind kind;
  std::string unit;
  double amplitude; ///< the column is amplitude * sin(t)
  int alias = 0;
};

/// A result of 50 rows over [0, 2] with `columns` after time.
SimResult makeResult(const std::vector<Column> &columns) {
  SimResult r;
  r.model = "Test";
  r.columns = {"time"};
  r.info = {ColumnInfo{ColumnKind::Time, "s", "", 0}};
  for (const Column &c : columns) {
    r.columns.push_back(c.name);
    r.info.push_back(ColumnInfo{c.kind, c.unit, "", c.alias});
  }
  for (int k = 0; k < 50; ++k) {
    double t = 2.0 * k / 49;
    std::vector<double> row = {t};
    for (const Column &c : columns)
      row.push_back(c.amplitude * std::sin(t));
    r.rows.push_back(row);
  }
  return r;
}

std::vector<std::string> names(const SimResult &r, const PlotPanel &p) {
  std::vector<std::string> out;
  for (int c : p.columns)
    out.push_back(r.columns[c]);
  return out;
}

/// `count` continuous curves of one unit and scale, named
/// `prefix` i `suffix` (i from 1).
SimResult arrayResult(const std::string &prefix, const std::string &suffix,
                      int count, const std::string &unit) {
  std::vector<Column> cols;
  for (int i = 1; i <= count; ++i)
    cols.push_back({prefix + std::to_string(i) + suffix,
                    ColumnKind::Continuous, unit, 1});
  return makeResult(cols);
}

using V = std::vector<std::string>;
constexpr ColumnKind Cont = ColumnKind::Continuous;

} // namespace

TEST(PlotPlan, GroupsByUnitAndSplitsScales) {
  SimResult r = makeResult({{"C.v", Cont, "V", 2},
                            {"L.i", Cont, "A", 0.5},
                            {"R.v", Cont, "V", 1},
                            {"sensor.v", Cont, "V", 1e-3},
                            {"der(C.v)", ColumnKind::Derivative, "V/s", 5},
                            {"R", ColumnKind::Parameter, "Ohm", 10},
                            {"C.p.v", Cont, "V", 2, /*alias of C.v*/ 1},
                            {"gain", Cont, "", 3}});
  auto plan = planPlot(r);
  ASSERT_TRUE(plan) << plan.error();
  ASSERT_EQ(plan->panels.size(), 4u);
  // Units in the order their first curve comes; within a unit the largest
  // scale first; curves in model order.
  EXPECT_EQ(names(r, plan->panels[0]), (V{"C.v", "R.v"}));
  EXPECT_EQ(plan->panels[0].label, "v [V]");
  EXPECT_EQ(names(r, plan->panels[1]), (V{"sensor.v"}));
  EXPECT_EQ(plan->panels[1].label, "sensor.v [V]");
  EXPECT_EQ(names(r, plan->panels[2]), (V{"L.i"}));
  EXPECT_EQ(plan->panels[2].label, "L.i [A]");
  EXPECT_EQ(names(r, plan->panels[3]), (V{"gain"}));
  EXPECT_EQ(plan->panels[3].label, "gain");
  EXPECT_TRUE(plan->leftOut.empty());
}

TEST(PlotPlan, MixedNamesLabelTheUnit) {
  SimResult r = makeResult({{"a.x", Cont, "m", 1}, {"b.y", Cont, "m", 2}});
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 1u);
  EXPECT_EQ(plan->panels[0].label, "[m]");
}

TEST(PlotPlan, TwoDecadesApartSplitMoreDoNot) {
  // 1 and 0.011 share a panel (less than 100 apart); 0.009 does not.
  SimResult r = makeResult({{"a", Cont, "V", 1},
                            {"b", Cont, "V", 0.011},
                            {"c", Cont, "V", 0.009},
                            {"zero", Cont, "V", 0}});
  auto plan = planPlot(r, {"a", "b", "c", "zero"});
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 2u);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"a", "b"}));
  // A curve that stays zero joins the smallest scale.
  EXPECT_EQ(names(r, plan->panels[1]), (V{"c", "zero"}));
}

TEST(PlotPlan, EvenPanelsOverTheCap) {
  SimResult r = arrayResult("C[", "].v", 10, "V");
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 2u);
  EXPECT_EQ(plan->panels[0].columns.size(), 5u);
  EXPECT_EQ(names(r, plan->panels[1]).front(), "C[6].v");
  EXPECT_EQ(plan->panels[1].label, "v [V]");
}

TEST(PlotPlan, ConstantCurvesLeftOutByDefault) {
  SimResult r = makeResult({{"ground.p.v", Cont, "V", 0},
                            {"C.v", Cont, "V", 1},
                            {"ground.p.i", Cont, "A", 0}});
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 1u);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"C.v"}));
  EXPECT_EQ(plan->constant, (V{"ground.p.v", "ground.p.i"}));
  // Named, or when every curve is constant, they are drawn.
  auto named = planPlot(r, {"ground.p.v", "C.v"});
  ASSERT_TRUE(named);
  EXPECT_EQ(names(r, named->panels[0]), (V{"ground.p.v", "C.v"}));
  EXPECT_TRUE(named->constant.empty());
  SimResult flat = makeResult({{"x", Cont, "", 0}});
  auto all = planPlot(flat);
  ASSERT_TRUE(all);
  EXPECT_EQ(names(flat, all->panels[0]), (V{"x"}));
}

TEST(PlotPlan, StatesByDefault) {
  // The model's unknowns (its states) among the continuous variables:
  // only those are drawn; names that are no column are ignored.
  SimResult r = makeResult({{"source.v", Cont, "V", 10},
                            {"C.v", Cont, "V", 12},
                            {"L.i", Cont, "A", 0.4},
                            {"mode", ColumnKind::Discrete, "", 1}});
  auto plan = planPlot(r, {}, {"C.v", "L.i", "solved.out"});
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 2u);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"C.v"}));
  EXPECT_EQ(plan->panels[0].label, "C.v [V]");
  EXPECT_EQ(names(r, plan->panels[1]), (V{"L.i"}));
  // No unknown among the columns: every continuous variable.
  auto none = planPlot(r, {}, {"elsewhere"});
  ASSERT_TRUE(none);
  EXPECT_EQ(names(r, none->panels[0]), (V{"source.v", "C.v"}));
  // Named columns win.
  auto named = planPlot(r, {"source.v"}, {"C.v"});
  ASSERT_TRUE(named);
  EXPECT_EQ(names(r, named->panels[0]), (V{"source.v"}));
}

TEST(PlotPlan, CapsCurvesAndPanels) {
  // 60 curves of one unit and scale: 8 a panel, 6 panels, 12 left out.
  SimResult r = arrayResult("T[", "]", 60, "K");
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), kPlotPanels);
  size_t drawn = 0;
  for (const PlotPanel &p : plan->panels) {
    EXPECT_LE(p.columns.size(), kPlotCurvesPerPanel);
    drawn += p.columns.size();
  }
  EXPECT_EQ(drawn, 48u);
  EXPECT_EQ(names(r, plan->panels[0]).front(), "T[1]");
  ASSERT_EQ(plan->leftOut.size(), 12u);
  EXPECT_EQ(plan->leftOut.front(), "T[49]");
  EXPECT_EQ(plan->leftOut.back(), "T[60]");
}

TEST(PlotPlan, NamedColumnsOnlyAnyKind) {
  SimResult r = makeResult({{"x", Cont, "", 1},
                            {"der(x)", ColumnKind::Derivative, "", 1},
                            {"k", ColumnKind::Parameter, "", 1}});
  auto plan = planPlot(r, {"der(x)", "k"});
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 1u);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"der(x)", "k"}));
  auto unknown = planPlot(r, {"y"});
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().find("'y'"), std::string::npos);
}

TEST(PlotPlan, WithoutColumnInfoOneGroupNoDerivatives) {
  SimResult r = makeResult({{"x", Cont, "", 1},
                            {"der(x)", ColumnKind::Derivative, "", 1},
                            {"y", Cont, "", 1}});
  r.info.clear(); // a result without metadata
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  ASSERT_EQ(plan->panels.size(), 1u);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"x", "y"}));
  EXPECT_EQ(plan->panels[0].unit, "");
}

TEST(PlotPlan, DiscreteWhenNothingContinuous) {
  SimResult r = makeResult({{"k", ColumnKind::Parameter, "", 1},
                            {"mode", ColumnKind::Discrete, "", 1}});
  auto plan = planPlot(r);
  ASSERT_TRUE(plan);
  EXPECT_EQ(names(r, plan->panels[0]), (V{"mode"}));
  SimResult onlyParams = makeResult({{"k", ColumnKind::Parameter, "", 1}});
  auto none = planPlot(onlyParams);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().find("nothing to plot"), std::string::npos);
  r.rows.clear(); // a run that failed before its first row
  auto empty = planPlot(r);
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error(), "nothing to plot: the run has no rows");
}

TEST(PlotPlan, ExtensionDecidesTheFormat) {
  SimResult r = makeResult({{"x", Cont, "", 1}});
  auto bad = plot(r, "out.eps");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find(".svg, .png or .pdf"), std::string::npos);
}
