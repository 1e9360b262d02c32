// The pass list (Passes.def), the pipeline of each method, and the runner:
// each pass in order, timing it (`--time-passes`) and printing what it
// left (`--print-after NAME`), stopping at the first pass that reports
// errors.
#include "passes/Passes.h"

#include "ir/Discrete.h"

#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>

namespace ldae::passes {

namespace {

const PassInfo kPassTable[] = {
#define PASS(Id, Name, Summary, Create) {Name, Summary},
#include "passes/Passes.def"
};

} // namespace

const PassInfo &passInfo(PassId id) {
  return kPassTable[static_cast<size_t>(id)];
}

const std::vector<PassInfo> &passList() {
  static const std::vector<PassInfo> list(std::begin(kPassTable),
                                          std::end(kPassTable));
  return list;
}

std::string passNames() {
  std::string all;
  for (const PassInfo &p : kPassTable)
    all += std::string(all.empty() ? "" : ", ") + p.name;
  return all;
}

void ResultStore::missing(const std::type_info &type) {
  std::cerr << "ldaec: internal error: a pass reads a result (" << type.name()
            << ") that no earlier pass of the pipeline produced\n";
  std::abort();
}

void Pass::print(PassContext &ctx, ResultStore &results,
                 std::ostream &out) const {
  // The sga pass makes an empty system unless it builds one (an
  // over-determined model): the model is what there is to print then.
  if (results.has<ir::DaeSystem>() &&
      !results.get<ir::DaeSystem>().stateSets.empty())
    out << printReduced(results.get<ir::DaeSystem>());
  else
    out << ctx.model.print();
}

PassPipeline pipelineFor(Method method) {
  PassPipeline p;
  // Every method sees only the continuous system; the discrete part goes
  // to the event update (docs/events.md).
  p.push_back(createEventsPass());
  // Every method reports the formal index of the model as written.
  p.push_back(createFormalIndexPass());
  switch (method) {
  case Method::Raw:
    // The model as written: Pantelides reports the index but hands on the
    // equations undifferentiated, so no derivative becomes a dummy; the
    // BLT may be singular; no pruning (the unreduced matching leaves
    // unknowns unmatched, so the walk from the outputs would drop what
    // determines them) and no initialization structure (meaningless above
    // index one).
    p.push_back(createAliasEliminationPass());
    p.push_back(createMatchingPass());
    p.push_back(createDmDiagnosisPass());
    p.push_back(createPantelidesPass({.reduce = false}));
    p.push_back(createDummyDerivativesPass());
    p.push_back(createBuildSystemPass());
    p.push_back(createBltPass({.allowSingular = true}));
    return p;
  case Method::Sga:
  case Method::Ode:
    // The vector field on P_f from the geometric algorithm, whatever the
    // model's size, and no structural index reduction.
    p.push_back(createLinearPencilPass());
    p.push_back(createSgaPass(/*always=*/true));
    p.push_back(createSgaSystemPass());
    return p;
  case Method::DummyDerivatives:
    // The SGA first, on the model as written, as a verdict (no solution,
    // not unique, redundant equations) and to cross-check the states
    // structure chooses.
    p.push_back(createLinearPencilPass());
    p.push_back(createSgaPass());
    p.push_back(createAliasEliminationPass());
    p.push_back(createMatchingPass());
    p.push_back(createDmDiagnosisPass());
    p.push_back(createPantelidesPass());
    p.push_back(createDummyDerivativesPass());
    p.push_back(createBuildSystemPass());
    p.push_back(createSgaCheckPass());
    p.push_back(createBltPass());
    p.push_back(createPrunePass());
    p.push_back(createCausalizePass());
    p.push_back(createInitializationPass());
    return p;
  }
  return p;
}

bool runPipeline(ir::Model &model, const PipelineOptions &opts,
                 DiagnosticEngine &diags, AnalysisResult &result) {
  result = AnalysisResult{};
  result.model = model.name;
  for (size_t k = 0; k < model.userParameterCount(); ++k)
    if (!model.parameters[k].isConstant)
      result.parameters.push_back(model.parameters[k].name);
  // The continuous system's counts (the discrete part is the events').
  const std::vector<bool> discrete = ir::discreteVariables(model);
  for (bool d : discrete)
    result.variables += d ? 0 : 1;
  for (const ir::Equation &e : model.equations)
    result.equations += ir::isDiscreteEquation(e.residual, discrete) ? 0 : 1;

  PassContext ctx(model, diags, opts, result);
  ctx.jumpsMatter = opts.keepStateAliases;
  ResultStore results;
  bool ok = true;
  for (const std::unique_ptr<Pass> &pass : pipelineFor(opts.method)) {
    auto t0 = std::chrono::steady_clock::now();
    ok = pass->run(ctx, results) && !diags.hasErrors();
    double secs = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - t0)
                      .count();
    result.timings.push_back({pass->name(), secs});
    if (opts.log)
      for (const std::string &name : opts.printAfter)
        if (name == pass->name()) {
          *opts.log << "// ---- after " << name << " ----\n";
          pass->print(ctx, results, *opts.log);
        }
    if (!ok || ctx.finished)
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
  // After the passes: some fold parameter values into the compiled model
  // (a discrete start value) and mark them structural.
  const std::vector<bool> structural = model.structuralParameters();
  for (size_t k = 0; k < model.userParameterCount(); ++k)
    if (!model.parameters[k].isConstant && structural[k])
      result.structuralParameters.push_back(model.parameters[k].name);
  if (ok && results.has<ir::DaeSystem>())
    result.system = std::move(results.get<ir::DaeSystem>());
  return ok;
}

} // namespace ldae::passes
