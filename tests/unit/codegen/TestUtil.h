// Helpers of the codegen tests: evaluating every function of an ldae_model
// at a point, comparing evaluations, compiling emitted C with the system
// compiler and loading it.
#pragma once

#include "codegen/Codegen.h"
#include "SampleSystems.h"

#include <string>
#include <vector>

namespace ldae::codegen::testing {

/// A point at which to evaluate a model.
struct Point {
  double t = 0, cj = 1;
  std::vector<double> y, yp, p;
};

/// Values and return codes of every function of a model at one point.
struct Evaluation {
  std::vector<std::string> labels; // which function each array came from
  std::vector<std::vector<double>> arrays;
  std::vector<int> codes;
};

Evaluation evaluateAll(const ldae_model &m, const Point &pt);

/// Checks a and b agree: same codes, values within `rel` relative.
/// Returns "" or a description of the first difference.
std::string compareEvaluations(const Evaluation &a, const Evaluation &b,
                               double rel);

/// Checks sizes, names, patterns and defaults agree.
std::string compareMetadata(const ldae_model &a, const ldae_model &b);

/// The p every function of `m` reads: the parameters' defaults, then the
/// discrete values and their pre() values at their starts.
std::vector<double> parameterVector(const ldae_model &m);

/// Random point: y, yp uniform in [lo, hi], p the parameters' defaults
/// and discrete values 0 or 1.
Point randomPoint(const ldae_model &m, unsigned seed, double lo, double hi);

/// Runs `command` through the shell; returns its exit status.
int run(const std::string &command);

/// A fresh directory under the test temp dir.
std::string makeTempDir(const std::string &stem);

/// The emitted C of `sys` compiled with `cc -O2 -shared -fPIC` and loaded.
class CLibrary {
public:
  CLibrary(const ir::DaeSystem &sys, const CodegenOptions &opts = {});
  ~CLibrary();
  CLibrary(const CLibrary &) = delete;
  CLibrary &operator=(const CLibrary &) = delete;
  /// Null when compiling or loading failed (see error()).
  const ldae_model *model() const { return model_; }
  const std::string &error() const { return error_; }

private:
  void *handle_ = nullptr;
  const ldae_model *model_ = nullptr;
  std::string error_;
};

/// The compiled model or a failed test.
std::unique_ptr<CompiledModel> compileOrDie(const ir::DaeSystem &sys,
                                            const CodegenOptions &opts);

} // namespace ldae::codegen::testing
