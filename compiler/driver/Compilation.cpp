#include "Compilation.h"

#include "OutputSelection.h"
#include "Validate.h"

#include "frontend/Frontend.h"
#include "ir/External.h"

#include <chrono>
#include <cstdlib>
#include <mutex>
#include <ostream>

namespace ldae::driver {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
      .count();
}

} // namespace

std::string defaultCacheDir() {
  if (const char *dir = std::getenv("LDAEC_CACHE_DIR"); dir && *dir)
    return dir;
  if (const char *xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/ldaec";
  if (const char *home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/ldaec";
  return "";
}

Compilation::Compilation(CompileRequest request, std::ostream &diagnostics)
    : request_(std::move(request)), out_(diagnostics), diags_(sources_) {
  diags_.setErrorLimit(50);
}

Compilation::~Compilation() = default;

bool Compilation::parse() {
  auto t0 = std::chrono::steady_clock::now();
  frontend::FrontendOptions feOpts;
  feOpts.modelName = request_.modelName;
  feOpts.paramOverrides = request_.overrides;
  feOpts.libraryPaths = request_.libraries;
  feOpts.cacheDir = request_.externalCacheDir.empty()
                       ? request_.codegen.cacheDir
                       : request_.externalCacheDir;
  if (request_.classOnPath) {
    // The class itself is the model, found on the library path.
    feOpts.modelName = request_.path;
    model_ = frontend::compileSource("<library path>", "", feOpts, sources_,
                                     diags_);
  } else {
    model_ = frontend::compileFile(request_.path, feOpts, sources_, diags_);
  }
  diags_.flush(out_);
  if (hasCommandLineError(diags_)) {
    exitCode_ = 2; // --model, --param or --override named nothing
    model_.reset();
    return false;
  }
  if (!model_) {
    exitCode_ = 1;
    return false;
  }
  if (!request_.outputs.empty()) {
    std::optional<std::vector<std::string>> names =
        selectOutputs(*model_, request_.outputs, diags_);
    diags_.flush(out_);
    if (!names) {
      exitCode_ = 2;
      return false;
    }
    request_.passes.outputs = std::move(*names);
  }
  // As many equations as unknowns: a warning that names what is missing or
  // left over. The geometric algorithm (the "sga" pass) gives the verdict:
  // redundant but consistent equations are solved without, too few or
  // conflicting ones are errors naming the free variables or the conflict.
  frontend::checkBalance(*model_, diags_);
  diags_.flush(out_);
  if (request_.passes.timePasses && request_.passes.log)
    *request_.passes.log << "frontend: " << secondsSince(t0) * 1e3 << " ms\n";
  return true;
}

namespace {
/// The first external object of `flat` whose handle was made when
/// compiling other than by a call of its constructor (an emitted program
/// cannot make it again: CodePlan::objects).
const ir::Parameter *firstUnmadeObject(const ir::Model &flat) {
  for (const ir::Parameter &p : flat.parameters)
    if (p.externalObject && !ir::isConstructorCall(p.binding))
      return &p;
  return nullptr;
}
} // namespace

bool Compilation::analyze() {
  // A model whose if-equations may change its structure keeps its flat
  // form: a run compiles each further mode from it when first reached.
  if (const ir::Equation *e = firstVariableIf(*model_)) {
    variableIf_ = e->loc;
    if (!request_.passes.reportOnly)
      flat_.emplace(*model_);
  }
  if (const ir::Parameter *p = firstUnmadeObject(*model_))
    unmadeObject_ = std::make_pair(p->loc, p->name);
  auto t0 = std::chrono::steady_clock::now();
  bool ok = passes::runPipeline(*model_, request_.passes, diags_, analysis_);
  if (request_.passes.timePasses && request_.passes.log)
    *request_.passes.log << "passes: " << secondsSince(t0) * 1e3 << " ms\n";
  diags_.flush(out_);
  if (!ok || (!request_.passes.reportOnly && !analysis_.system)) {
    exitCode_ = 1;
    return false;
  }
  return true;
}

bool Compilation::compile() {
  auto t0 = std::chrono::steady_clock::now();
  codegen::CodegenOptions cg = request_.codegen;
  cg.sources = &sources_;
  Expected<std::unique_ptr<codegen::CompiledModel>> code =
      codegen::compile(*analysis_.system, cg);
  if (!code) {
    diags_.report(DiagId::ErrCodegenFailed, SourceLoc{}, {code.error()});
    diags_.flush(out_);
    exitCode_ = 1;
    return false;
  }
  compiled_ = std::move(*code);
  compileSeconds_ = secondsSince(t0);
  if (request_.passes.timePasses && request_.passes.log)
    *request_.passes.log << "codegen: " << compileSeconds_ * 1e3 << " ms\n";
  if (flat_ && !analysis_.system->events.modeDiscrete.empty())
    modes_.emplace(*flat_, request_.passes, cg, diags_);
  return true;
}

Expected<std::string> Compilation::emitC(bool withMain, std::string &whyNot) {
  codegen::CodegenOptions cg = request_.codegen;
  cg.sources = &sources_;
  const ir::EventSystem &events = analysis_.system->events;
  if (events.modeDiscrete.empty() || !flat_)
    return codegen::emitC(*analysis_.system, withMain, cg);
  // The modes' own diagnostics (a structurally singular combination that
  // no run reaches) are not the user's.
  DiagnosticEngine modeDiags(sources_);
  ModeCompiler modes(*flat_, request_.passes, cg, modeDiags);
  auto all = modes.allModes(events);
  if (!all) {
    whyNot = all.error();
    return std::string();
  }
  std::vector<codegen::ModeSystem> ahead;
  for (const std::vector<double> &values : *all)
    if (auto sys = modes.system(values))
      ahead.push_back({values, *sys});
  return codegen::emitC(*analysis_.system, withMain, cg, ahead);
}

Expected<runtime::SimResult>
Compilation::simulate(runtime::SimOptions options) {
  if (modes_) {
    // Runs of a sweep share the modes compiled so far; one compiles at a
    // time.
    options.modeProvider = [this](const std::vector<double> &values) {
      std::lock_guard<std::mutex> lock(modesMutex_);
      return modes_->model(values);
    };
  }
  return runtime::simulate(compiled_->model(), options);
}

} // namespace ldae::driver
