// --outputs names and patterns against the flat model (selectOutputs):
// model order, array elements by index, der(x) after x, parameters after
// the variables, each name once, and the errors of what selects nothing.
#include "OutputSelection.h"
#include "frontend/Frontend.h"

#include <gtest/gtest.h>

namespace ldae::driver {
namespace {

using Names = std::vector<std::string>;

const char *kModel = R"(model Cells
  parameter Real k(unit = "1/s") = 2 "rate";
  Real T[11](each start = 0, each fixed = true, each unit = "K");
  Real e "energy";
  parameter Real w = 1;
equation
  der(T[1]) = k * (1 - T[1]);
  for i in 2:11 loop
    der(T[i]) = k * (T[i-1] - T[i]);
  end for;
  e = w * T[11];
end Cells;
)";

struct Selected {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<ir::Model> model;
  std::optional<Names> names;
};

std::unique_ptr<Selected> select(const Names &patterns) {
  auto s = std::make_unique<Selected>();
  frontend::FrontendOptions opts;
  s->model = frontend::compileSource("cells.lsd", kModel, opts, s->sources,
                                     s->diags);
  EXPECT_TRUE(s->model);
  if (s->model)
    s->names = selectOutputs(*s->model, patterns, s->diags);
  return s;
}

TEST(OutputSelection, GlobsInModelOrderWithNumericIndices) {
  auto s = select({"T[1?]", "T[2]"});
  ASSERT_TRUE(s->names);
  EXPECT_EQ(*s->names, (Names{"T[2]", "T[10]", "T[11]"}));
}

TEST(OutputSelection, DerivativesFollowTheirVariableAndParametersComeLast) {
  auto s = select({"k", "der(T[3])", "e", "T[3]", "T[3]"});
  ASSERT_TRUE(s->names);
  EXPECT_EQ(*s->names, (Names{"T[3]", "der(T[3])", "e", "k"}));
}

TEST(OutputSelection, StarMatchesEverythingOnce) {
  auto s = select({"*", "e"});
  ASSERT_TRUE(s->names);
  ASSERT_EQ(s->names->size(), 11u * 2 + 1 + 2);
  EXPECT_EQ((*s->names)[0], "T[1]");
  EXPECT_EQ((*s->names)[1], "der(T[1])");
  EXPECT_EQ(s->names->back(), "w");
}

TEST(OutputSelection, WhatSelectsNothingIsAnErrorWithCloseNames) {
  auto s = select({"T[12]", "q*", "e"});
  EXPECT_FALSE(s->names);
  const auto &d = s->diags.diagnostics();
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].id, DiagId::ErrUnknownOutputOptionSuggest);
  EXPECT_EQ(d[1].id, DiagId::ErrUnknownOutputOption);
}

TEST(OutputSelection, UnitsAndDescriptionsReachTheFlatModel) {
  auto s = select({"e"});
  const ir::Model &m = *s->model;
  EXPECT_EQ(m.parameters[*m.findParameter("k")].unit, "1/s");
  EXPECT_EQ(m.parameters[*m.findParameter("k")].description, "rate");
  EXPECT_EQ(m.parameters[*m.findParameter("w")].unit, "");
  EXPECT_EQ(m.variables[*m.findVariable("T[4]")].unit, "K");
  EXPECT_EQ(m.variables[*m.findVariable("e")].description, "energy");
}

} // namespace
} // namespace ldae::driver
