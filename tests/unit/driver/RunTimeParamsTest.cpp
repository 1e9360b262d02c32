// Compile once, run many: a compiled model run with other parameters and
// start values (runtime::SimOptions::params, ::starts, applied through the
// model's bind function) writes the same CSV, byte for byte, as the model
// recompiled with those values (--override), in both backends.
#include "Compilation.h"
#include "ldae/ResultWriter.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace ldae::driver {
namespace {

/// Chained bindings (k2 reads k, k3 reads k2, x0 reads k3), a start bound
/// to a parameter, a fixed start, and a structural parameter (n sizes v).
const char *kModel = R"(model Chain
  parameter Real k = 2;
  parameter Real k2 = 3*k;
  parameter Real k3 = k2 + 1;
  parameter Real x0 = k3/2;
  parameter Integer n = 2;
  constant Real c = 1;
  Real x(start = x0);
  Real z(start = 1, fixed = true);
  Real v[n];
  Real y;
equation
  der(x) = -k*x + k2;
  der(z) = -z;
  y = k3*x + c*z;
  for i in 1:n loop
    v[i] = i*y;
  end for;
end Chain;
)";

std::string modelFile() {
  static const std::string path = [] {
    std::string p = (std::filesystem::temp_directory_path() /
                     ("run_time_params_" + std::to_string(::getpid()) + ".lsd"))
                        .string();
    std::ofstream(p) << kModel;
    return p;
  }();
  return path;
}

struct Compiled {
  std::ostringstream diags;
  std::unique_ptr<Compilation> c;
};

std::unique_ptr<Compiled> compileWith(std::vector<std::string> overrides,
                                      bool jit) {
  auto out = std::make_unique<Compiled>();
  CompileRequest req;
  req.path = modelFile();
  req.overrides = std::move(overrides);
  req.codegen.jit = jit;
  out->c = std::make_unique<Compilation>(req, out->diags);
  EXPECT_TRUE(out->c->parse() && out->c->analyze() && out->c->compile())
      << out->diags.str();
  return out;
}

std::string csvOf(Compilation &c, runtime::SimOptions o) {
  o.stop = 2;
  o.interval = 0.25;
  auto r = c.simulate(o);
  EXPECT_TRUE(bool(r)) << (r ? "" : r.error());
  if (!r)
    return "";
  EXPECT_EQ(r->status, 0) << r->failure;
  std::ostringstream os;
  runtime::writeCsv(*r, os);
  return os.str();
}

class RunTimeParams : public ::testing::TestWithParam<bool> {};

TEST_P(RunTimeParams, SameCsvAsRecompiling) {
  auto once = compileWith({}, GetParam());
  runtime::SimOptions o;
  o.params = {{"k", 3}};
  std::string runTime = csvOf(*once->c, o);
  auto again = compileWith({"k=3"}, GetParam());
  EXPECT_EQ(runTime, csvOf(*again->c, {}));
  // The defaults again from the same compiled model: nothing left over.
  EXPECT_EQ(csvOf(*once->c, {}), csvOf(*compileWith({}, GetParam())->c, {}));
}

TEST_P(RunTimeParams, GivenParameterKeepsItsValue) {
  // k2 given: k3 and x0 follow k2, not k.
  auto once = compileWith({}, GetParam());
  runtime::SimOptions o;
  o.params = {{"k", 3}, {"k2", 5}};
  auto again = compileWith({"k=3", "k2=5"}, GetParam());
  EXPECT_EQ(csvOf(*once->c, o), csvOf(*again->c, {}));
}

TEST_P(RunTimeParams, StartValues) {
  // A start over a bound one, and a fixed start, as --override x.start.
  auto once = compileWith({}, GetParam());
  runtime::SimOptions o;
  o.params = {{"k", 3}};
  o.starts = {{"x", 0.5}, {"z", 4}};
  auto again = compileWith({"k=3", "x.start=0.5", "z.start=4"}, GetParam());
  EXPECT_EQ(csvOf(*once->c, o), csvOf(*again->c, {}));
}

INSTANTIATE_TEST_SUITE_P(Backends, RunTimeParams, ::testing::Bool(),
                         [](const auto &info) {
                           return info.param ? "Jit" : "Interpreter";
                         });

TEST(RunTimeParamsErrors, StructuralUnknownAndSolvedOut) {
  auto once = compileWith({}, false);
  auto error = [&](runtime::SimOptions o) {
    o.stop = 1;
    auto r = once->c->simulate(o);
    return r ? std::string("no error") : r.error();
  };
  runtime::SimOptions o;
  o.params = {{"n", 3}};
  EXPECT_EQ(error(o), "parameter 'n' fixes the model's structure (an array "
                      "size, a branch or a subscript): it cannot change "
                      "without recompiling");
  o.params = {{"c", 3}};
  EXPECT_EQ(error(o), "cannot override constant 'c'");
  o.params = {{"kk", 3}};
  EXPECT_EQ(error(o), "unknown parameter 'kk'; did you mean 'k', 'k2', 'k3'?");
  o.params = {};
  o.starts = {{"y", 1}};
  std::string e = error(o);
  EXPECT_EQ(e.rfind("the start value of 'y' cannot change without "
                    "recompiling: y is computed from other unknowns (",
                    0),
            0u)
      << e;
  o.starts = {{"xx", 1}};
  EXPECT_EQ(error(o).rfind("unknown variable 'xx'", 0), 0u)
      << error(o);
}

} // namespace
} // namespace ldae::driver
