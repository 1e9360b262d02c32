// Domain errors (the row named, the same in every backend and in the IR's
// reference evaluator, guards of `if`/`and` respected), built-ins at their
// branch points, layout errors, large chunked models, interpreter slots,
// the LLVM text, and the emitted C used as documented (docs/embedding-c.md):
// with the example program and with its main over the runtime (libldaert).
#include "TestUtil.h"

#include "codegen/Interpreter.h"
#include "ir/Evaluate.h"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <sstream>

using namespace ldae;
using namespace ldae::codegen;
using namespace ldae::codegen::testing;

namespace {

std::string readFile(const std::string &path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string runCapture(const std::string &command, int &status) {
  std::string out = makeTempDir("out") + "/stdout.txt";
  status = run(command + " > " + out + " 2>&1");
  return readFile(out);
}

/// Residual return code of every backend at y = {x, 0...}.
struct Codes {
  int jit, interp, c, reference;
};

class DomainErrors : public ::testing::Test {
protected:
  void SetUp() override {
    s = samples::domainErrors();
    jit = compileOrDie(s.sys, {});
    CodegenOptions o;
    o.jit = false;
    interp = compileOrDie(s.sys, o);
    lib = std::make_unique<CLibrary>(s.sys);
    ASSERT_TRUE(jit && interp && lib->model()) << lib->error();
  }
  Codes codesAt(double x) {
    const ldae_model &m = jit->model();
    std::vector<double> y(m.n, 0.0), yp(m.n, 0.0), r(m.n);
    y[0] = x;
    auto code = [&](const ldae_model &mm) {
      return mm.state_sets[0].residual(0, y.data(), yp.data(), nullptr,
                                       r.data());
    };
    Codes c{code(m), code(interp->model()), code(*lib->model()), 0};
    // The reference: 1 + the first row ir::evaluate rejects.
    ir::EvalEnv env;
    env.variable = [&](ir::VarKey k) { return k.var == 0 ? x : 0.0; };
    const auto &rows = s.sys.stateSets[0].residuals;
    for (size_t i = 0; i < rows.size() && !c.reference; ++i)
      if (!ir::evaluate(rows[i], env, s.sys.model))
        c.reference = int(i) + 1;
    return c;
  }
  samples::SampleSystem s;
  std::unique_ptr<CompiledModel> jit, interp;
  std::unique_ptr<CLibrary> lib;
};

TEST_F(DomainErrors, ReturnOneBasedRowInEveryBackend) {
  // x -> expected return code: the row of the first failing residual + 1.
  const std::pair<double, int> cases[] = {
      {2, 0},   // every row defined
      {150, 2}, // if x > 100 then log(x - 200): the guard holds, log fails
      {-1, 3},  // log(x); the `if`s of rows 1 and 5 guard their logs
      {0, 3},   // log(0)
      {0.5, 4}, // sqrt(x - 1)
      {3, 5},   // 1 / (x - 3)
      {9, 7},   // asin((x - 4) / 4)
      {5, 8},   // mod(x, x - 5)
      {6, 9},   // (x - 6.2)^1.5 in the taken branch of an if
      {5.5, 0}, // the same power in the branch not taken
  };
  for (auto [x, expected] : cases) {
    Codes c = codesAt(x);
    EXPECT_EQ(c.jit, expected) << "x = " << x;
    EXPECT_EQ(c.interp, expected) << "x = " << x;
    EXPECT_EQ(c.c, expected) << "x = " << x;
    EXPECT_EQ(c.reference, expected) << "x = " << x;
  }
}

TEST(Builtins, BranchPointsAgreeEverywhere) {
  auto s = samples::builtins();
  auto jit = compileOrDie(s.sys, {});
  CodegenOptions o;
  o.jit = false;
  auto interp = compileOrDie(s.sys, o);
  CLibrary lib(s.sys);
  ASSERT_TRUE(jit && interp && lib.model()) << lib.error();
  const ldae_model &m = jit->model();
  // u == v: abs, sign, min, max, if, or, not at their switch; 4u integral:
  // floor and ceil at a jump; 5u == 2v: mod at a jump.
  const std::pair<double, double> points[] = {
      {0.5, 0.5}, {0.25, 0.7}, {0.4, 1.0}, {0.75, 0.75}};
  for (auto [u, v] : points) {
    Point pt = randomPoint(m, 7, 0.1, 0.9);
    pt.y[0] = u;
    pt.y[1] = v;
    Evaluation a = evaluateAll(m, pt);
    EXPECT_EQ(compareEvaluations(a, evaluateAll(interp->model(), pt), 1e-13), "");
    EXPECT_EQ(compareEvaluations(a, evaluateAll(*lib.model(), pt), 1e-13), "");
    // Outputs equal the reference evaluator exactly at the switch.
    ir::EvalEnv env;
    env.time = pt.t;
    env.variable = [&](ir::VarKey k) { return k.var == 0 ? u : v; };
    env.parameter = [&](ir::ParamId p) { return pt.p[p]; };
    std::vector<double> out(m.n_outputs);
    ASSERT_EQ(m.outputs(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), out.data()), 0);
    for (int i = 0; i < m.n_outputs; ++i) {
      auto ref = ir::evaluate(s.sys.outputs[i].value, env, s.sys.model);
      ASSERT_TRUE(bool(ref));
      EXPECT_LE(std::fabs(*ref - out[i]), 1e-13 * std::fabs(*ref))
          << m.output_names[i] << " at u=" << u << " v=" << v;
    }
  }
  // Spot values at u == v == 0.5.
  std::vector<double> y(m.n, 0.0), yp(m.n, 0.0), out(m.n_outputs);
  y[0] = y[1] = 0.5;
  ASSERT_EQ(m.outputs(0, y.data(), yp.data(), m.param_values, out.data()), 0);
  std::map<std::string, double> byName;
  for (int i = 0; i < m.n_outputs; ++i)
    byName[m.output_names[i]] = out[i];
  EXPECT_EQ(byName["abs"], 0.0);
  EXPECT_EQ(byName["sign"], 0.0);
  EXPECT_EQ(byName["min"], 0.5);
  EXPECT_EQ(byName["max"], 0.5);
  EXPECT_EQ(byName["if"], 0.0);   // u > v is false: u - v
  EXPECT_EQ(byName["or"], 0.5);   // u == v holds: u
  EXPECT_EQ(byName["not"], 3.0);  // not (u <> v) holds
  EXPECT_EQ(byName["and"], 0.25); // u <= v and v >= 0.1: u * u
  EXPECT_EQ(byName["floor"], 1.0); // floor(2) * 0.5
  EXPECT_EQ(byName["ceil"], 1.0);
  EXPECT_EQ(byName["mod"], 0.0);   // mod(2.5, 0.5)
  EXPECT_DOUBLE_EQ(byName["pow7"], 1.0);
  EXPECT_DOUBLE_EQ(byName["inverse_square"], 4.0);
}

TEST(Layout, VariableOutsideTheLayoutIsAnError) {
  auto s = samples::robertson();
  ir::Variable w;
  w.name = "w";
  ir::VarId id = s.model->addVariable(w);
  auto &c = s.model->ctx();
  s.sys.outputs.push_back({"w2", c.mul(c.constant(2), c.var(id))});
  auto m = compile(s.sys, {});
  ASSERT_FALSE(m);
  EXPECT_EQ(m.error(), "in outputs: 'w' is neither an unknown nor the "
                       "derivative of a differential unknown of the system");
  // der(y3) of the algebraic y3 is no slot either.
  s = samples::robertson();
  auto &c2 = s.model->ctx();
  s.sys.roots.push_back(c2.var(2, 1));
  m = compile(s.sys, {});
  ASSERT_FALSE(m);
  EXPECT_EQ(m.error(), "in roots: 'der(y3)' is neither an unknown nor the "
                       "derivative of a differential unknown of the system");
}

TEST(Layout, WrongSizesAreErrors) {
  auto s = samples::robertson();
  s.sys.stateSets[0].residuals.pop_back();
  auto m = compile(s.sys, {});
  ASSERT_FALSE(m);
  EXPECT_EQ(m.error(), "state set 0 has 2 residuals for 3 unknowns");
}

TEST(Large, ChainOf10000IsChunkedAndAgrees) {
  auto s = samples::chain(10000);
  auto jit = compileOrDie(s.sys, {});
  CodegenOptions o;
  o.jit = false;
  auto interp = compileOrDie(s.sys, o);
  ASSERT_TRUE(jit && interp);
  const ldae_model &m = jit->model();
  EXPECT_EQ(m.n, 10000);
  EXPECT_EQ(m.state_sets[0].jac_nnz, 3 * 10000 - 2); // tridiagonal
  EXPECT_EQ(m.state_sets[0].jacobian_dense, nullptr); // above the threshold
  for (unsigned seed = 1; seed <= 2; ++seed) {
    Point pt = randomPoint(m, seed, -1, 1);
    EXPECT_EQ(compareEvaluations(evaluateAll(m, pt),
                                 evaluateAll(interp->model(), pt), 1e-13),
              "");
  }
}

TEST(Interpreter, SlotsAreReleased) {
  auto s = samples::robertson();
  CodegenOptions o;
  o.jit = false;
  // More models than slots exist over time; never more than one alive.
  for (int i = 0; i < 300; ++i) {
    auto m = compile(s.sys, o);
    ASSERT_TRUE(m) << "model " << i << ": " << m.error();
  }
  std::vector<std::unique_ptr<CompiledModel>> alive;
  std::string error;
  for (unsigned i = 0; i < kInterpreterSlots + 1 && error.empty(); ++i) {
    auto m = compile(s.sys, o);
    if (m)
      alive.push_back(std::move(*m));
    else
      error = m.error();
  }
  EXPECT_EQ(error, "too many interpreted functions alive at once (the limit "
                   "is 1024)");
}

TEST(Llvm, ModuleDefinesTheAbiFunctions) {
  auto s = samples::builtins();
  auto text = emitLlvm(s.sys);
  ASSERT_TRUE(text) << text.error();
  for (const char *needle :
       {"i32 @builtins_residual_0(double", "@builtins_jac_csc_0(double",
        "@builtins_init_jac_csc(double", "@builtins_outputs(double",
        "@llvm.sqrt.f64", "@tan(", "@atan2("})
    EXPECT_NE(text->find(needle), std::string::npos) << needle;
  // 35 unknowns: above LDAE_DENSE_THRESHOLD, so no dense Jacobians.
  EXPECT_EQ(text->find("@builtins_jac_dense_0"), std::string::npos);
  EXPECT_EQ(text->find("@builtins_init_jacobian("), std::string::npos);
}

TEST(EmbeddingC, ExampleProgramCallsTheEmittedModel) {
  auto s = samples::pendulum();
  auto text = emitC(s.sys, false);
  ASSERT_TRUE(text) << text.error();
  std::string dir = makeTempDir("embed");
  std::ofstream(dir + "/model.c") << *text;
  int status = run("cc -std=c99 -O2 -Wall -Werror -I" LDAE_RUNTIME_INCLUDE
                   " -o " + dir + "/embed " LDAE_EMBED_EXAMPLE " " + dir +
                   "/model.c -lm");
  ASSERT_EQ(status, 0);
  std::string out = runCapture(dir + "/embed", status);
  ASSERT_EQ(status, 0) << out;
  auto jit = compileOrDie(s.sys, {});
  const ldae_model &m = jit->model();
  std::vector<double> r(m.n);
  ASSERT_EQ(m.state_sets[0].residual(0, m.start_y, m.start_yp, m.param_values,
                                     r.data()),
            0);
  std::ostringstream expected;
  expected.precision(17);
  expected << "model pendulum: 7 unknowns, 2 state sets, "
           << m.state_sets[0].jac_nnz << " nonzeros\n";
  char line[64];
  for (int i = 0; i < m.n; ++i) {
    std::snprintf(line, sizeof line, "r[%d] = %.17g\n", i, r[i]);
    expected << line;
  }
  EXPECT_EQ(out.substr(0, expected.str().size()), expected.str());
  EXPECT_NE(out.find("J[0,0] = 10\n"), std::string::npos) << out; // cj * 1
}

TEST(EmbeddingC, MainRunsRobertsonWithTheRuntime) {
  auto s = samples::robertson();
  auto text = emitC(s.sys, true);
  ASSERT_TRUE(text) << text.error();
  std::string dir = makeTempDir("main");
  // The command the header prints ("cc -O2 <sym>.c -L... -lldaert ...
  // -o <sym>"), run in `dir`, strict C99.
  size_t at = text->find("     cc -O2");
  ASSERT_NE(at, std::string::npos) << text->substr(0, 600);
  std::string command = text->substr(at + 5, text->find('\n', at) - at - 5);
  size_t dotC = command.find(".c ");
  size_t symAt = command.rfind(' ', dotC) + 1;
  std::string sym = command.substr(symAt, dotC - symAt);
  EXPECT_NE(command.find(" -lldaert -Wl,-rpath,"), std::string::npos)
      << command;
  EXPECT_EQ(command.substr(command.size() - 4 - sym.size()), " -o " + sym);
  std::ofstream(dir + "/" + sym + ".c") << *text;
  int status =
      run("cd " + dir + " && cc -std=c99 -Wall -Werror" + command.substr(2));
  ASSERT_EQ(status, 0) << command;
  // stderr has the runtime's initialization report; the CSV is stdout.
  std::string csv = runCapture(
      "(" + dir + "/" + sym + " --rtol 1e-8 --atol 1e-12 2>/dev/null)", status);
  ASSERT_EQ(status, 0) << csv;
  std::istringstream in(csv);
  std::string header, row, last;
  std::getline(in, header);
  // The columns of --simulate: the derivative output is not one of them;
  // the parameters follow as constant columns.
  EXPECT_EQ(header, "time,y1,y2,y3,k1,k2,k3");
  int rows = 0;
  while (std::getline(in, row)) {
    last = row;
    ++rows;
  }
  EXPECT_EQ(rows, 11); // 0, 0.04, ..., 0.4 from the experiment annotation
  double t, y1, y2, y3;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%lf,%lf,%lf", &t, &y1, &y2, &y3),
            4);
  // Reference values at t = 0.4 (SUNDIALS idaRoberts_dns.out).
  EXPECT_DOUBLE_EQ(t, 0.4);
  EXPECT_NEAR(y1, 9.8517e-01, 1e-5);
  EXPECT_NEAR(y2, 3.3864e-05, 1e-9);
  EXPECT_NEAR(y3, 1.4794e-02, 1e-6);
  EXPECT_NEAR(y1 + y2 + y3, 1.0, 1e-10);
  // Bad command lines exit with 2.
  runCapture(dir + "/" + sym + " --bogus 1", status);
  EXPECT_EQ(status, 2);
  runCapture(dir + "/" + sym + " --param nope=1", status);
  EXPECT_EQ(status, 2);
}

} // namespace
