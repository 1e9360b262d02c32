#include "Options.h"

#include "codegen/Codegen.h"
#include "ldae/Simulation.h"
#include "passes/Pipeline.h"

#include <CLI/CLI.hpp>

namespace ldae::driver {

namespace {

std::vector<std::string> integratorSpellings() {
  std::vector<std::string> names;
  for (const runtime::IntegratorSpelling &s : runtime::kIntegratorSpellings)
    names.push_back(s.name);
  return names;
}

/// An option taking one word of `table`: checked against the words
/// first, so the conversion to `target` cannot fail.
template <typename E, size_t N>
void addChoice(CLI::App &app, const std::string &name, E &target,
               const Spelling<E> (&table)[N], const std::string &help) {
  app.add_option_function<std::string>(
         name,
         [&target, &table](const std::string &word) {
           target = *parseSpelling(table, word);
         },
         help)
      ->check(CLI::IsMember(spellings(table)));
}

} // namespace

void defineOptions(CLI::App &app, Options &o) {
  app.description(
      "ldaec: compiler for implicit differential systems written in lsd.\n"
      "Finds hidden constraints (any index), reduces the model, compiles it\n"
      "with LLVM and integrates it with SUNDIALS IDA.");
  app.add_option("model", o.input,
                 "the .lsd or .mo file to compile, or a class on the library "
                 "path (Modelica.Mechanics.Rotational.Examples.First)")
      ->required();
  app.add_option("--lib", o.libraries,
                 "a library directory, searched before those of MODELICAPATH "
                 "(the directory holding Modelica/ for the Modelica Standard "
                 "Library; repeatable)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--model", o.modelName,
                 "the model to compile (default: the last non-partial model)");
  app.add_option("--param", o.paramOverrides,
                 "override a parameter: --param name=value (repeatable)");
  app.add_option("--override", o.overrides,
                 "change values without editing the model, as the Modelica "
                 "tools do: --override R=2,C.start=1 (parameters by name, "
                 "start values as name.start; repeatable; what depends on "
                 "them follows)");

  app.add_flag("--analyze", o.analyze,
               "structural analysis report: index, states, dummies, DOF");
  app.add_flag("--json", o.json, "with --analyze: the report as JSON");
  app.add_flag("--simulate", o.simulate,
               "integrate the model, write the results (CSV, or .mat by -o's "
               "extension)");
  addChoice(app, "--emit", o.emit, kEmitSpellings,
            "print an intermediate form");
  app.add_flag("--main", o.emitMain,
               "with --emit c: add a main() that runs the model as --simulate "
               "does (links libldaert, docs/embedding-c.md)");
  app.add_option("-o,--output", o.outputFile,
                 "output file (default stdout); with --simulate the format "
                 "follows the extension: .mat the MATLAB v4 result layout of "
                 "OpenModelica and Dymola, anything else CSV "
                 "(docs/results.md)");
  app.add_option("--format", o.format,
                 "with --simulate: the result format whatever -o's "
                 "extension: csv or mat (mat needs -o FILE)")
      ->check(CLI::IsMember({"csv", "mat"}));

  app.add_option("--start", o.run.start, "start time");
  app.add_option("--stop", o.run.stop, "stop time");
  app.add_option("--rtol", o.run.rtol, "relative tolerance");
  app.add_option("--atol", o.run.atol,
                 "absolute tolerance (scaled by nominal)");
  app.add_option("--interval", o.run.interval, "output interval");
  app.add_flag("--every-step", o.run.everyStep,
               "output at every solver step");
  app.add_option("--output-times", o.run.times,
                 "output at exactly these increasing times instead of the "
                 "interval grid; the last is the default stop time: "
                 "--output-times 0.4,4,40")
      ->delimiter(',');
  addChoice(app, "--algebraic-error-test", o.run.algebraicErrorTest,
            kSwitchSpellings,
            "on: algebraic unknowns in IDA's local error test; off: "
            "left out; auto (default): on for index-1 systems (every "
            "reduced one), off for a higher-index system as written "
            "(--method raw)");
  // Checked against the spellings first, so the conversion cannot fail.
  app.add_option_function<std::string>(
         "--integrator",
         [&o](const std::string &i) {
           o.run.integrator = *runtime::parseIntegrator(i);
         },
         "auto (default): CVODE (BDF) for an explicit ODE, IDA "
         "for a DAE and for an explicit ODE whose computed "
         "variables stay in the error test (docs/runtime.md), and "
         "for --method sga|ode CVODE Adams moving "
         "to BDF when the model turns out stiff; ida; cvode (BDF) "
         "or cvode-bdf; cvode-adams (non-stiff); CVODE needs the "
         "ODE form (--analyze shows it) or --method sga|ode")
      ->check(CLI::IsMember(integratorSpellings()));
  // Checked against the spellings first, so the conversion cannot fail.
  app.add_option_function<std::string>(
         "--method",
         [&o](const std::string &m) { o.method = *passes::parseMethod(m); },
         "integration method: dd (default: index reduction by dummy "
         "derivatives, then IDA or CVODE); sga (the geometric algorithm's "
         "vector field on its final constraint manifold P_f, with CVODE, "
         "projected onto every constraint after each step); ode (the same "
         "without the projection: shows the drift); raw (the system as "
         "written)")
      ->check(CLI::IsMember(std::vector<std::string>(
          passes::kMethodSpellings.begin(), passes::kMethodSpellings.end())));
  app.add_option_function<std::string>(
         "--causalize",
         [&o](const std::string &c) {
           o.causalize =
               parseSpelling(kSwitchSpellings, c) == SwitchChoice::On;
         },
         "on: the integrator gets the states and the tearing "
         "variables only, the rest is computed in BLT order; off: "
         "every unknown of the index-1 system goes to the integrator")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--outputs", o.outputs,
                 "comma-separated variables and parameters to output, or "
                 "patterns: * any run of characters, ? one ('C[*].v', "
                 "'r1.*'); columns in model order; compiles only what they "
                 "need");
  app.add_option("--plot", o.plotFile,
                 "plot the outputs to .svg, .png or .pdf: one panel per "
                 "unit, labels and legend (docs/plots.md)");
  app.add_option("--sweep", o.sweep,
                 "run once per value: --sweep R=1:10:100 (100 values from 1 "
                 "to 10) or --sweep R=1,2,5; several --sweep make a grid of "
                 "every combination; one compile, the runs on --jobs threads, "
                 "every member in -o (docs/results.md, \"Sweeps\")");
  app.add_option("--jobs", o.jobs,
                 "with --sweep: members run at once (default 0: the cores)")
      ->check(CLI::Range(0, 4096));
  app.add_flag("--no-cache", o.noCache,
               "with --simulate: neither read nor write the cache of "
               "compiled models ($LDAEC_CACHE_DIR, else "
               "$XDG_CACHE_HOME/ldaec, else ~/.cache/ldaec)");
  app.add_flag("--stats", o.stats,
               "print solver statistics on stderr: steps, evaluations, "
               "roots, events, time events, mode switches, jumps, the backend and "
               "the object cache (hit or miss)");
  app.add_flag("--no-progress", o.noProgress, "never show a progress bar");
  addChoice(app, "--jit", o.jit, kSwitchSpellings,
            "on: compile with the LLVM JIT; off: run the plan "
            "interpreter (no LLVM loaded); auto (default): the "
            "interpreter for small models, the JIT above " +
                std::to_string(codegen::kAutoJitWork) +
                " operations per evaluation (docs/codegen.md)");

  app.add_flag("--time-passes", o.timePasses, "time every stage and pass");
  app.add_flag("--compile-only", o.compileOnly,
               "with --simulate: stop once the model is compiled and ready "
               "to integrate (for timing the compiler)");
  app.add_option("--print-after", o.printAfter,
                 "print what the named pass left (repeatable); the passes "
                 "in order: " +
                     passes::passNames());
}

} // namespace ldae::driver
