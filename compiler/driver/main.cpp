// The ldaec command: the whole pipeline, top to bottom, in one place.
//   parse/flatten -> passes -> codegen -> runtime
// Exit codes (docs/exit-codes.md): 0 success, 1 the model is wrong (or
// out of memory), 2 bad command line, 3 numerical failure during
// simulation.
#include "Options.h"
#include "Validate.h"

#include "frontend/Frontend.h"
#include "codegen/Codegen.h"
#include "ModeCompiler.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"
#include "Plot.h"
#include "ResultWriter.h"
#include "ldae/Simulation.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include <chrono>
#include <optional>
#include <fstream>
#include <iostream>
#include <unistd.h>

using namespace ldae;

/// Writes `text` to `path`, or to stdout when `path` is empty.
static bool writeOutput(const std::string &path, const std::string &text) {
  if (path.empty()) {
    std::cout << text;
    return true;
  }
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) {
    std::cerr << "ldaec: error: cannot write '" << path << "'\n";
    return false;
  }
  return true;
}

/// Reports a stage's finished message through the diagnostics table and
/// returns the exit code `rc` for the caller to pass on.
static int reportError(DiagnosticEngine &diags, DiagId id,
                       const std::string &message, int rc) {
  diags.report(id, SourceLoc{}, {message});
  diags.flush(std::cerr);
  return rc;
}

static int run(int argc, char **argv) {
  driver::Options opts;
  CLI::App app;
  app.set_version_flag("--version", std::string("ldaec ") + LDAEC_VERSION);
  driver::defineOptions(app, opts);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  {
    // A bad command line costs no work: checked before the model is read.
    SourceManager noSources;
    DiagnosticEngine cmdDiags(noSources);
    bool ok = driver::checkCommandLine(app, opts, cmdDiags);
    cmdDiags.flush(std::cerr);
    if (!ok)
      return 2;
  }

  // 1. Parse, check and flatten the model.
  auto stageStart = std::chrono::steady_clock::now();
  auto msSince = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(
               std::chrono::steady_clock::now() - t0)
        .count();
  };
  SourceManager sources;
  DiagnosticEngine diags(sources);
  diags.setErrorLimit(50);
  frontend::FrontendOptions feOpts;
  feOpts.modelName = opts.modelName;
  feOpts.paramOverrides = opts.paramOverrides;
  std::unique_ptr<ir::Model> model =
      frontend::compileFile(opts.input, feOpts, sources, diags);
  diags.flush(std::cerr);
  if (driver::hasCommandLineError(diags))
    return 2; // --model or --param named nothing in the file
  if (!model)
    return 1;
  bool outputsExist = driver::checkAgainstModel(opts, *model, diags);
  diags.flush(std::cerr);
  if (!outputsExist)
    return 2;

  // 2. As many equations as unknowns: a warning that names what is
  // missing or left over. The geometric algorithm (the "sga" pass) gives
  // the verdict: redundant but consistent equations are solved without,
  // too few or conflicting ones are errors naming the free variables or
  // the conflict.
  frontend::checkBalance(*model, diags);
  diags.flush(std::cerr);
  if (opts.timePasses)
    std::cerr << "frontend: " << msSince(stageStart) << " ms\n";

  if (opts.emit == "flat")
    return writeOutput(opts.outputFile, model->print()) ? 0 : 1;

  // 3. Structural analysis, index reduction, initialization (passes).
  passes::PipelineOptions passOpts;
  passOpts.method = opts.method;
  // `--emit reduced` shows the index-1 system index reduction built; the
  // causal form has no lsd text of its own (its assignments are folded
  // into the residuals).
  passOpts.causalize = opts.causalize == "on" && opts.emit != "reduced";
  passOpts.outputs = driver::splitOutputs(opts.outputs);
  passOpts.timePasses = opts.timePasses;
  passOpts.reportOnly = opts.analyze || (!opts.simulate && opts.emit.empty());
  passOpts.printAfter = opts.printAfter;
  passOpts.log = &std::cerr;
  passes::AnalysisResult analysis;
  // A model whose if-equations may change its structure keeps its flat
  // form: the run compiles each further mode from it when first reached.
  std::optional<ir::Model> flat;
  std::optional<SourceLoc> variableIf;
  if (const ir::Equation *e = driver::firstVariableIf(*model)) {
    variableIf = e->loc;
    if (opts.simulate)
      flat.emplace(*model);
  }
  stageStart = std::chrono::steady_clock::now();
  bool analyzed = passes::runPipeline(*model, passOpts, diags, analysis);
  if (opts.timePasses)
    std::cerr << "passes: " << msSince(stageStart) << " ms\n";
  diags.flush(std::cerr);
  if (opts.analyze) {
    // The report says what can be said, even about a singular model.
    if (opts.json)
      std::cout << passes::analysisToJson(analysis).dump(2) << "\n";
    else
      passes::printAnalysis(analysis, std::cout);
    return analyzed ? 0 : 1;
  }
  if (!analyzed || !analysis.system)
    return 1;
  if (opts.emit == "reduced")
    return writeOutput(opts.outputFile, passes::printReduced(*analysis.system))
               ? 0
               : 1;

  // 4. Code generation: LLVM JIT (or the interpreter), or text.
  codegen::CodegenOptions cgOpts;
  if (opts.jit == "auto")
    cgOpts.jit.reset(); // by the size of the model
  else
    cgOpts.jit = opts.jit == "on";
  cgOpts.sources = &sources;
  if (opts.emit == "c" && !analysis.system->events.modeDiscrete.empty()) {
    diags.report(DiagId::ErrVariableStructureC,
                 variableIf.value_or(SourceLoc{}));
    diags.flush(std::cerr);
    return 1;
  }
  if (opts.emit == "llvm" || opts.emit == "c") {
    Expected<std::string> text =
        opts.emit == "llvm"
            ? codegen::emitLlvm(*analysis.system, cgOpts)
            : codegen::emitC(*analysis.system, opts.emitMain, cgOpts);
    if (!text)
      return reportError(diags, DiagId::ErrCodegenFailed, text.error(), 1);
    return writeOutput(opts.outputFile, *text) ? 0 : 1;
  }
  if (!opts.simulate) {
    // No action asked: the model checked out; say what it is.
    passes::printAnalysis(analysis, std::cout);
    return 0;
  }
  auto compileStart = std::chrono::steady_clock::now();
  Expected<std::unique_ptr<codegen::CompiledModel>> compiled =
      codegen::compile(*analysis.system, cgOpts);
  if (!compiled)
    return reportError(diags, DiagId::ErrCodegenFailed, compiled.error(), 1);
  double compileSeconds = std::chrono::duration<double>(
                              std::chrono::steady_clock::now() - compileStart)
                              .count();
  if (opts.timePasses)
    std::cerr << "codegen: " << compileSeconds * 1e3 << " ms\n";
  if (opts.compileOnly)
    return 0; // ready to integrate: what compile-time benchmarks measure

  // 5. Integrate and write the results.
  runtime::SimOptions simOpts;
  simOpts.start = opts.startTime;
  simOpts.stop = opts.stopTime;
  simOpts.rtol = opts.rtol;
  simOpts.atol = opts.atol;
  simOpts.interval = opts.interval;
  simOpts.everyStep = opts.everyStep;
  simOpts.times = opts.outputTimes;
  if (!opts.stopTime && !opts.outputTimes.empty())
    simOpts.stop = opts.outputTimes.back(); // explicit times end the run
  if (opts.algebraicErrorTest != "auto")
    simOpts.algebraicErrorTest = opts.algebraicErrorTest == "on";
  // Checked against the spellings on the command line.
  simOpts.integrator = *runtime::parseIntegrator(opts.integrator);
  simOpts.outputs = passOpts.outputs;
  if (simOpts.outputs.empty()) {
    // By default the model's own variables; derivatives only when asked.
    const ldae_model &m = (*compiled)->model();
    for (int i = 0; i < m.n_outputs; ++i)
      if (std::string(m.output_names[i]).rfind("der(", 0) != 0)
        simOpts.outputs.push_back(m.output_names[i]);
  }
  std::optional<driver::ModeCompiler> modes;
  if (flat && !analysis.system->events.modeDiscrete.empty()) {
    modes.emplace(*flat, passOpts, cgOpts, diags);
    simOpts.modeProvider = [&](const std::vector<double> &values) {
      return modes->model(values);
    };
  }
  simOpts.progress = !opts.noProgress && isatty(STDERR_FILENO);
  simOpts.log = &std::cerr;
  Expected<runtime::SimResult> result =
      runtime::simulate((*compiled)->model(), simOpts);
  if (!result)
    return reportError(diags, DiagId::ErrSimulationOptions, result.error(), 2);
  if (result->status != 0)
    reportError(diags, DiagId::ErrSimulationFailed, result->failure, 3);
  Expected<bool> written = runtime::writeCsv(
      *result, opts.outputFile.empty() ? std::string("-") : opts.outputFile);
  if (!written)
    return reportError(diags, DiagId::ErrorGeneric, written.error(), 1);
  int rc = result->status == 0 ? 0 : 3;
  if (!opts.plotFile.empty()) {
    // The CSV is written either way; a plot asked for and not made is still
    // an error.
    Expected<bool> plotted = runtime::plot(*result, opts.plotFile);
    if (!plotted && rc == 0)
      rc = 1;
    if (!plotted)
      reportError(diags, DiagId::ErrPlotFailed, plotted.error(), rc);
  }
  if (opts.stats) {
    std::cerr << "compile time: " << compileSeconds << " s\n";
    if (modes)
      std::cerr << fmt::format("modes compiled during the run {} ({:.3f} s)\n",
                               modes->compiled(), modes->seconds());
    std::cerr << codegen::describeBackend((*compiled)->backend()) << "\n";
    runtime::printStats(result->stats, std::cerr);
  }
  return rc;
}

int main(int argc, char **argv) {
  // Nothing may end in an abort trace: running out of memory (a model too
  // large for this machine) and any other escaping exception end with one
  // line and exit 1 (docs/exit-codes.md).
  SourceManager noSources;
  DiagnosticEngine diags(noSources);
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc &) {
    std::cout.flush();
    return reportError(diags, DiagId::ErrOutOfMemory, "", 1);
  } catch (const std::exception &e) {
    std::cout.flush();
    return reportError(diags, DiagId::ErrInternalException, e.what(), 1);
  }
}
