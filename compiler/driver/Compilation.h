// One model taken through the compiler's stages, for every front end that
// runs it: the ldaec command (main.cpp calls the stages in order and adds
// what the command line asks in between) and the Python module (which
// compiles once and simulates many times with other parameters).
//   parse -> analyze -> compile -> simulate
// Each stage reports through one DiagnosticEngine into the stream given at
// construction, and returns false (or an Error) with the exit code the
// command would give (docs/exit-codes.md).
#pragma once

#include "ModeCompiler.h"

#include "codegen/Codegen.h"
#include "ir/Model.h"
#include "ldae/Simulation.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"
#include "support/SourceManager.h"

#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ldae::driver {

/// What to compile, and how: the compile part of the command line.
struct CompileRequest {
  std::string path;      ///< the .lsd file
  std::string modelName; ///< --model ("" : the last non-partial model)
  /// `path` names a class on the library path, not a file.
  bool classOnPath = false;
  std::vector<std::string> libraries; ///< --lib, before MODELICAPATH
  /// Where compiled external C code is kept ("": a temporary directory):
  /// the object cache's directory, also when nothing is JIT-compiled, since
  /// `--emit flat` evaluates external calls of parameters too.
  std::string externalCacheDir;
  /// Values fixed before analysis (--param name=value, --override
  /// name=value and name.start=value): structural parameters, and start
  /// values that cannot change at run time, go here.
  std::vector<std::string> overrides;
  /// --outputs: names and patterns (`C[*].v`, `r1.*`), expanded against
  /// the flat model in model order by parse().
  std::vector<std::string> outputs;
  passes::PipelineOptions passes;   ///< `outputs` is filled by parse()
  codegen::CodegenOptions codegen;
};

class Compilation {
public:
  /// Diagnostics are written to `diagnostics` as each stage ends.
  Compilation(CompileRequest request, std::ostream &diagnostics);
  ~Compilation();

  /// 1. Parse, check and flatten; expand the output patterns; the balance
  /// warning. False when the model is wrong (exitCode() 1) or the request
  /// names what the model lacks (exitCode() 2).
  bool parse();
  /// 2. Structural analysis, index reduction, the reduced system (or only
  /// the report, with `passes.reportOnly`). The report is filled even when
  /// this fails.
  bool analyze();
  /// 3. Code generation to a runnable model (JIT or interpreter, with the
  /// object cache when `codegen.cacheDir` is set).
  bool compile();
  /// 4. Integrates the compiled model; variable-structure models get their
  /// further modes compiled as the run reaches them. An Error for bad
  /// options (exit 2); a numerical failure is status 3 in the result.
  Expected<runtime::SimResult> simulate(runtime::SimOptions options);

  /// `--emit c [--main]` after analyze(): the C file. A variable-structure
  /// model's modes are compiled into it ahead (every combination of its
  /// mode values; one that cannot be analysed is left out, and a run that
  /// reaches it ends with status 3); when they cannot be enumerated,
  /// `whyNot` says why (the text is empty).
  Expected<std::string> emitC(bool withMain, std::string &whyNot);

  /// The exit code of the stage that failed (0 while none did).
  int exitCode() const { return exitCode_; }
  const CompileRequest &request() const { return request_; }
  /// After parse(): the flat model (analyze() transforms it in place).
  ir::Model &model() { return *model_; }
  /// After analyze().
  const passes::AnalysisResult &analysis() const { return analysis_; }
  /// After compile().
  const codegen::CompiledModel &compiled() const { return *compiled_; }
  double compileSeconds() const { return compileSeconds_; }
  /// The modes compiled during runs (null for one structure).
  const ModeCompiler *modes() const { return modes_ ? &*modes_ : nullptr; }
  /// Where a variable-structure model's if-equation is (for the error of
  /// `--emit c`); unset for one structure.
  std::optional<SourceLoc> variableStructure() const { return variableIf_; }
  /// Where and which external object's handle an emitted program could
  /// not make again (for the error of `--emit c`); unset without one.
  std::optional<std::pair<SourceLoc, std::string>> unmadeObject() const {
    return unmadeObject_;
  }
  SourceManager &sources() { return sources_; }
  DiagnosticEngine &diagnostics() { return diags_; }

private:
  CompileRequest request_;
  std::ostream &out_;
  SourceManager sources_;
  DiagnosticEngine diags_;
  std::unique_ptr<ir::Model> model_;
  std::optional<ir::Model> flat_; // kept for the modes of a run
  std::optional<SourceLoc> variableIf_;
  std::optional<std::pair<SourceLoc, std::string>> unmadeObject_;
  passes::AnalysisResult analysis_;
  std::unique_ptr<codegen::CompiledModel> compiled_;
  std::optional<ModeCompiler> modes_;
  std::mutex modesMutex_;
  double compileSeconds_ = 0;
  int exitCode_ = 0;
};

/// The default cache directory of compiled models: $LDAEC_CACHE_DIR, else
/// $XDG_CACHE_HOME/ldaec, else $HOME/.cache/ldaec ("" when none is set).
std::string defaultCacheDir();

} // namespace ldae::driver
