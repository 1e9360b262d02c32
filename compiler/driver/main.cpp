// The ldaec command: the whole pipeline, top to bottom, in one place.
//   parse/flatten -> passes -> codegen -> runtime
// The stages themselves are driver::Compilation's (shared with the Python
// module); this file says which run for which command line.
// Exit codes (docs/exit-codes.md): 0 success, 1 the model is wrong (or
// out of memory), 2 bad command line, 3 numerical failure during
// simulation.
#include "Options.h"
#include "RunRequest.h"
#include "Validate.h"

#include "Compilation.h"

#include "codegen/Codegen.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"
#include "ldae/Plot.h"
#include "ldae/ResultWriter.h"
#include "Interrupt.h"
#include "ldae/Rebind.h"
#include "ldae/Sweep.h"
#include "ldae/Simulation.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>
#include <csignal>

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

/// The compile part of the command line.
static driver::CompileRequest compileRequest(const driver::Options &opts) {
  driver::CompileRequest req;
  req.path = opts.input;
  req.modelName = opts.modelName;
  req.libraries = opts.libraries;
  req.classOnPath = driver::isClassName(opts.input);
  req.overrides = opts.paramOverrides;
  for (const std::string &list : opts.overrides)
    for (std::string &o : driver::splitOutputs(list))
      req.overrides.push_back(std::move(o));
  req.outputs = driver::splitOutputs(opts.outputs);
  driver::CompileChoices choices;
  choices.method = opts.method;
  choices.jit = opts.jit;
  if (opts.simulate && !opts.noCache)
    choices.cacheDir = driver::defaultCacheDir();
  if (!opts.noCache)
    req.externalCacheDir = driver::defaultCacheDir();
  driver::applyCompileChoices(choices, req);
  passes::PipelineOptions &p = req.passes;
  // `--emit reduced` shows the index-1 system index reduction built; the
  // causal form has no lsd text of its own (its assignments are folded
  // into the residuals).
  p.causalize = opts.causalize && opts.emit != driver::EmitKind::Reduced;
  p.timePasses = opts.timePasses;
  p.reportOnly = opts.analyze ||
                 (!opts.simulate && opts.emit == driver::EmitKind::None);
  p.printAfter = opts.printAfter;
  p.log = &std::cerr;
  return req;
}

/// `--sweep`: one run per member of the grid, on --jobs threads.
static int runSweep(driver::Compilation &c, const driver::Options &opts,
                    const runtime::SimOptions &sim,
                    runtime::ResultFormat format) {
  std::vector<runtime::SweepAxis> axes;
  for (const std::string &spec : opts.sweep)
    axes.push_back(*runtime::parseSweepAxis(spec)); // checked: exit 2
  runtime::SimOptions base = sim;
  base.progress = false; // one line per member instead
  // A name the model does not have is a bad command line, found before
  // any member runs (it failed each of 50,000 members in turn).
  std::vector<std::map<std::string, double>> grid = runtime::sweepMembers(axes);
  if (!grid.empty()) {
    std::map<std::string, double> params = base.params;
    for (const auto &[name, value] : grid.front())
      params[name] = value;
    Expected<runtime::BoundValues> bound = runtime::bindValues(
        c.compiled().model(), params, base.starts, base.start.value_or(0.0));
    if (!bound)
      return reportError(c.diagnostics(), DiagId::ErrSimulationOptions,
                         "--sweep: " + bound.error(), 2);
  }
  std::vector<runtime::SweepMember> members = runtime::runSweep(
      [&c](const runtime::SimOptions &o) { return c.simulate(o); }, base,
      std::move(grid), opts.jobs,
      opts.noProgress ? nullptr : &std::cerr);
  Expected<bool> written = runtime::writeSweep(
      members, opts.outputFile.empty() ? std::string("-") : opts.outputFile,
      format);
  if (!written)
    return reportError(c.diagnostics(), DiagId::ErrorGeneric, written.error(),
                       1);
  int failed = 0;
  for (const runtime::SweepMember &m : members)
    failed += !m.result || m.result->status != 0;
  if (failed)
    std::cerr << fmt::format("ldaec: {} of {} members failed (status in the "
                             "result file)\n",
                             failed, members.size());
  if (int signal = driver::InterruptGuard::received())
    return 128 + signal; // the members so far are in the result file
  return failed ? 3 : 0;
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
  driver::Compilation c(compileRequest(opts), std::cerr);

  // 1. Parse, check and flatten the model; expand --outputs.
  if (!c.parse())
    return c.exitCode();
  if (opts.emit == driver::EmitKind::Flat)
    return writeOutput(opts.outputFile, c.model().print()) ? 0 : 1;

  // 2. Structural analysis, index reduction, initialization (passes).
  bool analyzed = c.analyze();
  const passes::AnalysisResult &analysis = c.analysis();
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
  if (opts.emit == driver::EmitKind::Reduced)
    return writeOutput(opts.outputFile, passes::printReduced(*analysis.system))
               ? 0
               : 1;

  // 3. Code generation: text, or a runnable model (JIT or interpreter).
  // The program makes the model's external objects again, by their
  // constructors (CodePlan::objects).
  if (opts.emit == driver::EmitKind::C && c.unmadeObject()) {
    c.diagnostics().report(DiagId::ErrExternalObjectC, c.unmadeObject()->first,
                           {c.unmadeObject()->second});
    c.diagnostics().flush(std::cerr);
    return 1;
  }
  if (opts.emit == driver::EmitKind::C) {
    std::string whyNot;
    Expected<std::string> text = c.emitC(opts.emitMain, whyNot);
    if (!whyNot.empty()) {
      c.diagnostics().report(DiagId::ErrVariableStructureC,
                             c.variableStructure().value_or(SourceLoc{}),
                             {whyNot});
      c.diagnostics().flush(std::cerr);
      return 1;
    }
    if (!text)
      return reportError(c.diagnostics(), DiagId::ErrCodegenFailed,
                         text.error(), 1);
    return writeOutput(opts.outputFile, *text) ? 0 : 1;
  }
  if (opts.emit == driver::EmitKind::Llvm) {
    codegen::CodegenOptions cg = c.request().codegen;
    cg.sources = &c.sources();
    Expected<std::string> text = codegen::emitLlvm(*analysis.system, cg);
    if (!text)
      return reportError(c.diagnostics(), DiagId::ErrCodegenFailed,
                         text.error(), 1);
    return writeOutput(opts.outputFile, *text) ? 0 : 1;
  }
  if (!opts.simulate) {
    // No action asked: the model checked out; say what it is.
    passes::printAnalysis(analysis, std::cout);
    return 0;
  }
  if (!c.compile())
    return c.exitCode();
  if (opts.compileOnly)
    return 0; // ready to integrate: what compile-time benchmarks measure

  // 4. Integrate and write the results.
  driver::RunRequest run = opts.run;
  run.progress = !opts.noProgress && isatty(STDERR_FILENO);
  runtime::SimOptions sim = driver::runOptions(run, c.request());
  sim.log = &std::cerr;
  // Checked on the command line (exit 2 before any work).
  runtime::ResultFormat format =
      *runtime::resultFormat(opts.outputFile, opts.format);
  // A signal during the run ends it at its next step; its rows are written
  // (docs/results.md, "When a run is interrupted").
  driver::InterruptGuard guard;
  sim.interrupted = [] { return driver::InterruptGuard::received() != 0; };
  if (!opts.sweep.empty())
    return runSweep(c, opts, sim, format);
  // The rows go to the result file as the run produces them, so a long run
  // holds none of them (docs/results.md); a plot needs them all.
  const std::string outPath =
      opts.outputFile.empty() ? std::string("-") : opts.outputFile;
  std::unique_ptr<runtime::ResultFile> file;
  if (opts.plotFile.empty()) {
    auto opened = runtime::ResultFile::open(outPath, format);
    if (!opened)
      return reportError(c.diagnostics(), DiagId::ErrorGeneric, opened.error(),
                         1);
    file = std::move(*opened);
    sim.rowSink = file.get();
  }
  Expected<runtime::SimResult> result = c.simulate(sim);
  if (!result)
    return reportError(c.diagnostics(), DiagId::ErrSimulationOptions,
                       result.error(), 2);
  const int signal = result->interrupted ? driver::InterruptGuard::received()
                                         : 0;
  if (signal)
    std::cerr << fmt::format("ldaec: {}: the run stopped at t = {:.10g}; its "
                             "{} rows are written to {}\n",
                             signal == SIGINT ? "SIGINT" : "SIGTERM",
                             result->lastTime, result->rowCount,
                             outPath == "-" ? std::string("standard output")
                                            : "'" + outPath + "'");
  else if (result->status != 0)
    reportError(c.diagnostics(), DiagId::ErrSimulationFailed, result->failure,
                3);
  Expected<bool> written = file ? file->finish(*result)
                                : runtime::writeResult(*result, outPath,
                                                       format);
  // A row the file refused ended the run: that is the error to report
  // (the file's own outcome says also what became of the partial file).
  if (written && !result->writeFailure.empty())
    written = Error{result->writeFailure};
  if (!written)
    return reportError(c.diagnostics(), DiagId::ErrorGeneric, written.error(),
                       1);
  int rc = signal ? 128 + signal : result->status == 0 ? 0 : 3;
  if (!opts.plotFile.empty()) {
    // The results are written either way; a plot asked for and not made is
    // still an error.
    // The columns asked for, else the states (docs/plots.md).
    Expected<bool> plotted =
        runtime::plot(*result, opts.plotFile, sim.outputs,
                      runtime::unknownNames(c.compiled().model()));
    if (!plotted && rc == 0)
      rc = 1;
    if (!plotted)
      reportError(c.diagnostics(), DiagId::ErrPlotFailed, plotted.error(), rc);
  }
  if (opts.stats) {
    std::cerr << "compile time: " << c.compileSeconds() << " s\n";
    if (const driver::ModeCompiler *modes = c.modes())
      std::cerr << fmt::format("modes compiled during the run {} ({:.3f} s)\n",
                               modes->compiled(), modes->seconds());
    std::cerr << codegen::describeBackend(c.compiled().backend()) << "\n";
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
