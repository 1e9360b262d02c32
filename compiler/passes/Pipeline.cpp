// The pass list, in one place, and the function that runs it: each pass in
// order, timing it (`--time-passes`) and printing the state after it
// (`--print-after NAME`), stopping at the first pass that reports errors.
#include "passes/AnalysisState.h"

#include "ir/Print.h"

#include <chrono>
#include <iomanip>
#include <ostream>

namespace ldae::passes {

namespace {

struct PassEntry {
  PassInfo info;
  bool (*run)(AnalysisState &);
};

const std::vector<PassEntry> &passTable() {
  static const std::vector<PassEntry> table = {
      {{"alias", "remove a = b, a = -b and a = constant equations"},
       runAliasElimination},
      {{"matching", "match equations to unknowns (orders merged)"},
       runMatching},
      {{"dm", "Dulmage-Mendelsohn diagnosis of a structurally singular model"},
       runDmDiagnosis},
      {{"pantelides", "find the equations to differentiate and how often"},
       runPantelides},
      {{"dummy-derivatives", "choose states and dummy derivatives; build the "
                             "index-1 system"},
       runDummyDerivatives},
      {{"blt", "block lower triangular order of the index-1 system"}, runBlt},
      {{"prune", "keep only what the requested outputs need"}, runPrune},
      {{"init", "initialization system: degrees of freedom, fixed values"},
       runInitialization},
  };
  return table;
}

void printState(const AnalysisState &s, const std::string &pass,
                std::ostream &out) {
  out << "// ---- after " << pass << " ----\n";
  if (pass == "alias" || pass == "matching" || pass == "dm") {
    out << s.model.print();
    return;
  }
  if (pass == "pantelides") {
    for (const DifferentiatedEquation &d : s.result.differentiated)
      out << "// differentiated " << d.times << "x: " << d.equation << "  ("
          << d.location << ")\n";
    for (const Row &r : s.rows)
      out << "0 = " << ir::printLsd(r.residual, &s.model) << ";  // "
          << s.equationText(s.equations[r.equation]) << " d/dt^" << r.times
          << "\n";
    return;
  }
  if (s.haveSystem)
    out << printReduced(s.system);
}

} // namespace

const std::vector<PassInfo> &passList() {
  static const std::vector<PassInfo> list = [] {
    std::vector<PassInfo> l;
    for (const PassEntry &e : passTable())
      l.push_back(e.info);
    return l;
  }();
  return list;
}

bool runPipeline(ir::Model &model, const PipelineOptions &opts,
                 DiagnosticEngine &diags, AnalysisResult &result) {
  result = AnalysisResult{};
  result.model = model.name;
  for (const ir::Variable &v : model.variables)
    result.variables += v.isDiscrete ? 0 : 1;
  result.equations = static_cast<int>(model.equations.size());

  AnalysisState state(model, diags, opts, result);
  bool ok = true;
  for (const PassEntry &pass : passTable()) {
    auto t0 = std::chrono::steady_clock::now();
    ok = pass.run(state) && !diags.hasErrors();
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - t0)
                      .count();
    result.timings.push_back({pass.info.name, secs});
    if (opts.log)
      for (const std::string &name : opts.printAfter)
        if (name == pass.info.name)
          printState(state, name, *opts.log);
    if (!ok)
      break;
  }
  if (opts.timePasses && opts.log) {
    std::ostream &out = *opts.log;
    double total = 0;
    for (const PassTiming &t : result.timings)
      total += t.seconds;
    out << "===-------------------------------------------===\n"
        << "  pass execution time (total " << std::fixed
        << std::setprecision(4) << total << " s)\n";
    for (const PassTiming &t : result.timings)
      out << "  " << std::setw(10) << t.seconds << " s  " << t.name << "\n";
    out << std::defaultfloat;
  }
  if (ok && state.haveSystem)
    result.system = std::move(state.system);
  return ok;
}

} // namespace ldae::passes
