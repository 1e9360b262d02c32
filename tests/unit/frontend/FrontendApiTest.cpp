// The frontend's public API on small models: what the flat model holds
// (names, attributes, origins, locations, component paths, source text).
#include "frontend/Frontend.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace ldae;

namespace {

struct Compiled {
  SourceManager sources;
  DiagnosticEngine diags{sources};
  std::unique_ptr<ir::Model> model;
};

std::unique_ptr<Compiled> compile(const std::string &text,
                                  frontend::FrontendOptions opts = {}) {
  auto c = std::make_unique<Compiled>();
  opts.libraryPaths = {std::string(LDAE_SOURCE_DIR) + "/stdlib"};
  c->model = frontend::compileSource("test.lsd", text, opts, c->sources, c->diags);
  return c;
}

size_t countOrigin(const ir::Model &m, ir::EquationOrigin o) {
  return std::count_if(m.equations.begin(), m.equations.end(),
                       [&](const ir::Equation &e) { return e.origin == o; });
}

} // namespace

TEST(FrontendApi, FlatNamesLocationsAndText) {
  auto c = compile("model M\n"
                   "  parameter Real k = 2;\n"
                   "  Real x(start = 1, fixed = true);\n"
                   "  Real e = 0.5 * x^2;\n"
                   "equation\n"
                   "  der(x) = -k * x;\n"
                   "end M;\n");
  ASSERT_TRUE(c->model) << c->diags.diagnostics().size();
  const ir::Model &m = *c->model;
  ASSERT_EQ(m.variables.size(), 2u);
  EXPECT_EQ(m.variables[0].name, "x");
  EXPECT_EQ(m.variables[0].start, 1);
  EXPECT_TRUE(m.variables[0].fixed);
  EXPECT_EQ(m.variables[0].loc.line, 3u);
  EXPECT_EQ(m.variables[0].loc.col, 8u);
  ASSERT_EQ(m.parameters.size(), 1u);
  EXPECT_EQ(m.parameters[0].value, 2);
  ASSERT_EQ(m.equations.size(), 2u);
  EXPECT_EQ(m.equations[0].origin, ir::EquationOrigin::Binding);
  EXPECT_EQ(m.equations[0].text, "e = 0.5 * x^2");
  EXPECT_EQ(m.equations[1].origin, ir::EquationOrigin::Declared);
  EXPECT_EQ(m.equations[1].text, "der(x) = -k * x");
  EXPECT_EQ(m.equations[1].loc.line, 6u);
  EXPECT_EQ(m.equations[1].loc.col, 3u);
  EXPECT_TRUE(frontend::checkBalance(m, c->diags));
}

TEST(FrontendApi, ConnectionOriginsAndComponents) {
  auto c = compile("model C\n"
                   "  Electrical.Resistor r(R = 5);\n"
                   "  Electrical.Capacitor cap(C = 2);\n"
                   "  Electrical.Ground g;\n"
                   "equation\n"
                   "  connect(r.n, cap.p);\n"
                   "  connect(cap.n, g.p);\n"
                   "  connect(r.p, g.p);\n"
                   "end C;\n");
  ASSERT_TRUE(c->model);
  const ir::Model &m = *c->model;
  // r, cap: 6 unknowns each; g: 2.
  EXPECT_EQ(m.variables.size(), 14u);
  EXPECT_EQ(countOrigin(m, ir::EquationOrigin::Connection), 3u);
  EXPECT_EQ(countOrigin(m, ir::EquationOrigin::FlowSum), 2u);
  EXPECT_EQ(countOrigin(m, ir::EquationOrigin::UnconnectedFlow), 0u);
  EXPECT_EQ(m.equations.size(), 14u);
  auto r = m.findVariable("r.p.v");
  ASSERT_TRUE(r);
  EXPECT_EQ(m.variables[*r].component, "r.p");
  auto R = m.findParameter("r.R");
  ASSERT_TRUE(R);
  EXPECT_EQ(m.parameters[*R].value, 5);
  EXPECT_EQ(m.parameters[*R].component, "r");
  for (const ir::Equation &e : m.equations)
    EXPECT_TRUE(e.loc.valid()) << e.text;
  EXPECT_TRUE(frontend::checkBalance(m, c->diags));
}

TEST(FrontendApi, OverridesSizeArrays) {
  frontend::FrontendOptions opts;
  opts.paramOverrides = {"n=5"};
  auto c = compile("model A\n"
                   "  parameter Integer n = 2;\n"
                   "  Real x[n];\n"
                   "equation\n"
                   "  for i in 1:n loop\n"
                   "    der(x[i]) = -i * x[i];\n"
                   "  end for;\n"
                   "end A;\n",
                   opts);
  ASSERT_TRUE(c->model);
  EXPECT_EQ(c->model->variables.size(), 5u);
  EXPECT_EQ(c->model->variables[4].name, "x[5]");
  EXPECT_EQ(c->model->equations.size(), 5u);
}

TEST(FrontendApi, SecondDerivativeIsOrderTwo) {
  auto c = compile("model P\n  Real q;\nequation\n  der(der(q)) = -q;\nend P;\n");
  ASSERT_TRUE(c->model);
  ir::ExprRef r = c->model->equations[0].residual;
  bool found = false;
  std::function<void(ir::ExprRef)> visit = [&](ir::ExprRef e) {
    if (e->kind() == ir::ExprKind::Variable && e->order() == 2)
      found = true;
    for (ir::ExprRef o : e->operands())
      visit(o);
  };
  visit(r);
  EXPECT_TRUE(found);
}

TEST(FrontendApi, ErrorsReturnNull) {
  auto c = compile("model B\n  Real x;\nequation\n  x = y;\nend B;\n");
  EXPECT_FALSE(c->model);
  ASSERT_EQ(c->diags.errorCount(), 1u);
  EXPECT_EQ(c->diags.diagnostics()[0].message, "use of undefined name 'y'");
}
