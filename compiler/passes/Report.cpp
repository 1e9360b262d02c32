// The `--analyze` report, as text and as JSON (docs/analysis-json.md).
#include "passes/Pipeline.h"

#include <nlohmann/json.hpp>

#include <ostream>

namespace ldae::passes {

namespace {
std::string joined(const std::vector<std::string> &items) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i)
    out += (i ? ", " : "") + items[i];
  return out.empty() ? "(none)" : out;
}

/// The causal form: what the integrator owns, and the blocks that are not
/// plain assignments (a large model has thousands of those).
void printCausal(const CausalResult &c, std::ostream &out) {
  if (!c.applied) {
    if (!c.integratorUnknowns.empty())
      out << "  integrator unknowns:  " << c.integratorUnknowns.size()
          << " (not causalized)\n";
    return;
  }
  int count[5] = {0, 0, 0, 0, 0};
  for (const CausalBlock &b : c.blocks)
    ++count[static_cast<int>(b.kind)];
  using K = CausalBlock::Kind;
  out << "  causal blocks:        " << c.blocks.size() << " ("
      << count[int(K::Explicit)] << " explicit, " << count[int(K::Derivative)]
      << " derivative, " << count[int(K::Nonlinear)] << " nonlinear, "
      << count[int(K::Kept)] << " kept, " << count[int(K::Loop)]
      << " torn loops)\n";
  out << "  computed explicitly:  " << c.explicitCount << " unknowns\n";
  for (const CausalBlock &b : c.blocks) {
    if (b.kind == CausalBlock::Kind::Explicit ||
        b.kind == CausalBlock::Kind::Derivative)
      continue;
    out << "    " << causalBlockKindName(b.kind) << " of "
        << b.variables.size() << ": iteration variables "
        << joined(b.iteration) << "; " << b.residuals << " residual"
        << (b.residuals == 1 ? "" : "s");
    if (!b.reason.empty())
      out << " (" << b.reason << ")";
    std::vector<std::string> where;
    for (const std::string &e : b.equations)
      if (!e.empty() && (where.empty() || where.back() != e))
        where.push_back(e);
    if (!where.empty())
      out << "  (" << joined(where) << ")";
    out << "\n";
  }
  out << "  integrator unknowns:  " << c.integratorUnknowns.size() << " ("
      << c.integratorUnknowns.size() - c.iterationVariables << " states, "
      << c.iterationVariables << " iteration variables): "
      << joined(c.integratorUnknowns) << "\n";
  out << "  form:                 "
      << (c.ode ? "ODE x' = f(t, x)" : "DAE F(t, x, x', z) = 0") << "\n";
}

nlohmann::json causalJson(const CausalResult &c) {
  nlohmann::json blocks = nlohmann::json::array();
  for (const CausalBlock &b : c.blocks)
    blocks.push_back({{"kind", causalBlockKindName(b.kind)},
                      {"size", b.variables.size()},
                      {"variables", b.variables},
                      {"equations", b.equations},
                      {"iteration", b.iteration},
                      {"residuals", b.residuals},
                      {"reason", b.reason}});
  return {{"applied", c.applied},
          {"form", c.ode ? "ode" : "dae"},
          {"unknowns_before", c.unknownsBefore},
          {"explicit", c.explicitCount},
          {"torn_loops", c.tornLoops},
          {"iteration_variables", c.iterationVariables},
          {"blocks", blocks}};
}

template <typename T> nlohmann::json optionalJson(const std::optional<T> &v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
} // namespace

void printAnalysis(const AnalysisResult &r, std::ostream &out) {
  out << "model " << r.model << "\n";
  out << "  variables:            " << r.variables << "\n";
  out << "  equations:            " << r.equations << "\n";
  out << "  aliases removed:      " << r.aliasesRemoved << "\n";
  if (r.singular) {
    out << "  structurally singular\n";
    if (!r.overDetermined.empty())
      out << "  over-determined:      " << joined(r.overDetermined) << "\n";
    if (!r.underDetermined.empty())
      out << "  undetermined:         " << joined(r.underDetermined) << "\n";
    return;
  }
  if (r.structuralIndex)
    out << "  structural index:     " << *r.structuralIndex << "\n";
  if (r.differentiationIndex)
    out << "  differentiation index: " << *r.differentiationIndex
        << " (structural)\n";
  out << "  degrees of freedom:   " << r.dof << "\n";
  out << "  states:               " << joined(r.states) << "\n";
  out << "  dummy derivatives:    " << joined(r.dummies) << "\n";
  if (!r.differentiated.empty()) {
    out << "  differentiated equations:\n";
    for (const DifferentiatedEquation &d : r.differentiated)
      out << "    " << d.times << "x  " << d.equation
          << (d.location.empty() ? "" : "  (" + d.location + ")") << "\n";
  }
  if (!r.bltBlocks.empty()) {
    int largest = 0;
    for (int b : r.bltBlocks)
      largest = std::max(largest, b);
    out << "  BLT blocks:           " << r.bltBlocks.size() << " (largest "
        << largest << ")\n";
  }
  out << "  system unknowns:      " << r.systemUnknowns << "\n";
  printCausal(r.causal, out);
  if (r.prunedUnknowns > 0)
    out << "  pruned unknowns:      " << r.prunedUnknowns << "\n";
  if (r.stateSets.size() > 1) {
    out << "  candidate state sets: " << r.stateSets.size() << "\n";
    for (size_t i = 0; i < r.stateSets.size(); ++i)
      out << "    " << i << ": states " << joined(r.stateSets[i].states)
          << (i == 0 ? "  (at start)" : "") << "\n";
  }
  if (r.init.analyzed) {
    out << "  initialization:       " << r.init.unknowns << " unknowns, "
        << r.init.equations << " equations, " << r.init.dof
        << " degrees of freedom\n";
    out << "    fixed:              " << joined(r.init.fixed) << "\n";
    if (!r.init.toFree.empty())
      out << "    to free:            " << joined(r.init.toFree) << "\n";
  }
}

nlohmann::json analysisToJson(const AnalysisResult &r) {
  nlohmann::json j;
  j["model"] = r.model;
  j["variables"] = r.variables;
  j["equations"] = r.equations;
  j["aliases_removed"] = r.aliasesRemoved;
  j["aliases"] = r.aliases;
  j["singular"] = r.singular;
  j["structural_index"] = optionalJson(r.structuralIndex);
  j["differentiation_index"] = optionalJson(r.differentiationIndex);
  j["dof"] = r.singular ? nlohmann::json(nullptr) : nlohmann::json(r.dof);
  j["states"] = r.states;
  j["dummies"] = r.dummies;
  nlohmann::json diffs = nlohmann::json::array();
  for (const DifferentiatedEquation &d : r.differentiated)
    diffs.push_back(
        {{"equation", d.equation}, {"location", d.location}, {"times", d.times}});
  j["differentiated"] = diffs;
  j["blt"] = r.bltBlocks;
  j["over_determined"] = r.overDetermined;
  j["undetermined"] = r.underDetermined;
  j["system_unknowns"] = r.systemUnknowns;
  j["pruned_unknowns"] = r.prunedUnknowns;
  j["integrator_unknowns"] = r.causal.integratorUnknowns;
  j["causal"] = causalJson(r.causal);
  nlohmann::json sets = nlohmann::json::array();
  for (const StateSetReport &s : r.stateSets)
    sets.push_back({{"states", s.states},
                    {"dummies", s.dummies},
                    {"pivot_size", s.pivotSize},
                    {"pivot", s.pivot}});
  j["state_sets"] = sets;
  if (r.init.analyzed)
    j["init"] = {{"unknowns", r.init.unknowns},
                 {"equations", r.init.equations},
                 {"dof", r.init.dof},
                 {"fixed", r.init.fixed},
                 {"honoured", r.init.honoured},
                 {"conflicting", r.init.conflicting},
                 {"to_free", r.init.toFree},
                 {"guesses", r.init.guesses},
                 {"initial_equations", r.init.initialEquations},
                 {"consistent", r.init.consistent}};
  else
    j["init"] = nullptr;
  j["outcome"] = nullptr;
  j["constraints"] = nullptr;
  j["free_functions"] = nullptr;
  j["linear"] = nullptr;
  return j;
}

} // namespace ldae::passes
