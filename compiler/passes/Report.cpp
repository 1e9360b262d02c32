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

const char *outcomeName(SgaReport::Outcome o) {
  switch (o) {
  case SgaReport::Outcome::Unique:
    return "unique";
  case SgaReport::Outcome::NotUnique:
    return "not_unique";
  case SgaReport::Outcome::NoSolution:
    return "no_solution";
  }
  return "";
}

void printSga(const SgaReport &s, std::ostream &out) {
  out << "  geometric algorithm:  ";
  switch (s.outcome) {
  case SgaReport::Outcome::Unique:
    out << "unique, dim P_f = " << s.dof;
    break;
  case SgaReport::Outcome::NotUnique:
    out << "not unique (" << s.freeFunctions << " free function"
        << (s.freeFunctions == 1 ? "" : "s") << "), dim P_f = " << s.dof;
    break;
  case SgaReport::Outcome::NoSolution:
    out << "no solution (P_f empty)";
    break;
  }
  out << "; " << s.generations.size() << " constraint generation"
      << (s.generations.size() == 1 ? "" : "s") << " in " << s.steps
      << " step" << (s.steps == 1 ? "" : "s") << "\n";
  for (size_t g = 0; g < s.generations.size(); ++g)
    for (const SgaConstraint &c : s.generations[g])
      out << "    generation " << g + 1 << ":       " << c.expr << " = 0\n";
  if (s.conflict)
    out << "    cannot hold:        " << s.conflict->expr << " = 0\n";
  if (!s.undetermined.empty())
    out << "    undetermined:       " << joined(s.undetermined) << "\n";
  if (!s.redundant.empty())
    out << "    redundant:          " << joined(s.redundant) << "\n";
  if (!s.point.empty()) {
    out << "    the only point:     ";
    for (size_t i = 0; i < s.point.size(); ++i)
      out << (i ? ", " : "") << s.point[i].first << " = " << s.point[i].second;
    out << "\n";
  }
}

nlohmann::json sgaConstraintsJson(const SgaReport &s) {
  nlohmann::json gens = nlohmann::json::array();
  for (const std::vector<SgaConstraint> &g : s.generations) {
    nlohmann::json list = nlohmann::json::array();
    for (const SgaConstraint &c : g)
      list.push_back({{"expr", c.expr}, {"from", c.from}});
    gens.push_back(list);
  }
  return gens;
}

/// The Wong-sequence verdict of a linear model (the "linear" pass).
void printLinear(const LinearReport &l, std::ostream &out) {
  out << "  linear pencil (Wong): "
      << (l.regular ? "regular, index " + std::to_string(l.index)
                    : std::string("singular: not well-posed"))
      << ", dim V = " << l.dimV << ", dim W = " << l.dimW << "\n";
  if (!l.freeDirections.empty())
    for (size_t i = 0; i < l.freeDirections.size(); i += 8) {
      // Eight to a line: a large singular model may leave hundreds free.
      std::vector<std::string> line(
          l.freeDirections.begin() + i,
          l.freeDirections.begin() +
              std::min(i + 8, l.freeDirections.size()));
      out << (i ? "                        " : "    free directions:    ")
          << joined(line) << "\n";
    }
  if (l.freeCount > l.freeDirections.size())
    out << "                        (and "
        << l.freeCount - l.freeDirections.size() << " more)\n";
  if (!l.conflict.empty())
    out << "    conflict:           " << l.conflict << "\n";
}

nlohmann::json linearJson(const LinearReport &l) {
  return {{"regular", l.regular},
          {"index", l.regular ? nlohmann::json(l.index)
                              : nlohmann::json(nullptr)},
          {"dim_V", l.dimV},
          {"dim_W", l.dimW},
          {"free_directions", l.freeDirections},
          {"free_count", l.freeCount},
          {"conflict", l.conflict.empty() ? nlohmann::json(nullptr)
                                          : nlohmann::json(l.conflict)}};
}

template <typename T> nlohmann::json optionalJson(const std::optional<T> &v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
} // namespace

static void printEvents(const EventsReport &e, std::ostream &out) {
  out << "  discrete values:      " << joined(e.discrete) << "\n";
  if (!e.roots.empty())
    out << "  event roots:          " << joined(e.roots) << "\n";
  if (!e.timeThresholds.empty())
    out << "  time events:          " << joined(e.timeThresholds) << "\n";
  if (e.samples || e.reinits || e.asserts)
    out << "  samples, reinits, asserts: " << e.samples << ", " << e.reinits
        << ", " << e.asserts << "\n";
  if (!e.mode.empty())
    out << "  structure chosen by:  " << joined(e.mode) << "\n";
}

void printAnalysis(const AnalysisResult &r, std::ostream &out) {
  out << "model " << r.model << "\n";
  out << "  variables:            " << r.variables << "\n";
  out << "  equations:            " << r.equations << "\n";
  out << "  aliases removed:      " << r.aliasesRemoved << "\n";
  if (!r.structuralParameters.empty())
    // The others change at run time (--param of an emitted program, the
    // Python module's simulate(params=...)) without a recompile.
    out << "  structural parameters: " << joined(r.structuralParameters)
        << "\n";
  out << "  formal index:         ";
  if (r.formalIndex) {
    out << *r.formalIndex << " (dim R_q^(s):";
    for (int d : r.formalDimensions)
      out << " " << d;
    out << ")\n";
  } else {
    out << "not computed (" << r.formalIndexNote << ")\n";
  }
  if (r.events)
    printEvents(*r.events, out);
  if (r.sga)
    printSga(*r.sga, out);
  else if (!r.sgaNote.empty())
    out << "  geometric algorithm:  not run (" << r.sgaNote << ")\n";
  if (r.linear)
    printLinear(*r.linear, out);
  if (r.sga && r.sga->outcome != SgaReport::Outcome::Unique)
    return; // structural analysis did not run
  if (r.singular) {
    out << "  structurally singular\n";
    if (!r.overDetermined.empty())
      out << "  over-determined:      " << joined(r.overDetermined) << "\n";
    if (!r.underDetermined.empty())
      out << "  undetermined:         " << joined(r.underDetermined) << "\n";
    return;
  }
  // Each index says which system it is of where they differ: alias
  // elimination can remove the equations structure differentiates.
  if (r.structuralIndexAsWritten && r.structuralIndex &&
      *r.structuralIndexAsWritten != *r.structuralIndex)
    out << "  structural index:     " << *r.structuralIndexAsWritten
        << " as written (Pryce); " << *r.structuralIndex
        << " after alias elimination\n";
  else if (r.structuralIndex)
    out << "  structural index:     " << *r.structuralIndex << "\n";
  if (r.differentiationIndex)
    out << "  differentiation index: " << *r.differentiationIndex << "\n";
  out << "  degrees of freedom:   " << r.dof;
  if (r.structuralDof)
    out << " (structure finds " << *r.structuralDof << ")";
  out << "\n";
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
  j["parameters"] = r.parameters;
  j["structural_parameters"] = r.structuralParameters;
  j["variables"] = r.variables;
  j["equations"] = r.equations;
  j["aliases_removed"] = r.aliasesRemoved;
  j["aliases"] = r.aliases;
  j["singular"] = r.singular;
  j["structural_index"] = optionalJson(r.structuralIndex);
  j["structural_index_as_written"] = optionalJson(r.structuralIndexAsWritten);
  j["differentiation_index"] = optionalJson(r.differentiationIndex);
  j["formal_index"] = optionalJson(r.formalIndex);
  if (r.events)
    j["events"] = {{"discrete", r.events->discrete},
                   {"roots", r.events->roots},
                   {"time_thresholds", r.events->timeThresholds},
                   {"samples", r.events->samples},
                   {"reinits", r.events->reinits},
                   {"asserts", r.events->asserts},
                   {"mode", r.events->mode}};
  else
    j["events"] = nullptr;
  if (r.sga && r.sga->outcome != SgaReport::Outcome::NoSolution)
    j["dof"] = r.sga->dof;
  else
    j["dof"] = r.singular ? nlohmann::json(nullptr) : nlohmann::json(r.dof);
  j["structural_dof"] = optionalJson(r.structuralDof);
  j["states"] = r.states;
  j["dummies"] = r.dummies;
  nlohmann::json diffs = nlohmann::json::array();
  for (const DifferentiatedEquation &d : r.differentiated)
    diffs.push_back(
        {{"equation", d.equation}, {"location", d.location}, {"times", d.times}});
  j["differentiated"] = diffs;
  j["blt"] = r.bltBlocks;
  j["over_determined"] = r.overDetermined;
  j["undetermined"] = r.sga ? r.sga->undetermined : r.underDetermined;
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
  if (r.sga) {
    j["outcome"] = outcomeName(r.sga->outcome);
    j["constraints"] = sgaConstraintsJson(*r.sga);
    j["free_functions"] = r.sga->freeFunctions;
    j["redundant"] = r.sga->redundant;
    j["sga_steps"] = r.sga->steps;
    j["conflict"] = r.sga->conflict
                        ? nlohmann::json{{"expr", r.sga->conflict->expr},
                                         {"from", r.sga->conflict->from}}
                        : nlohmann::json(nullptr);
    nlohmann::json point = nlohmann::json::object();
    for (const auto &[name, value] : r.sga->point)
      point[name] = value;
    j["point"] = r.sga->point.empty() ? nlohmann::json(nullptr) : point;
  } else {
    j["outcome"] = nullptr;
    j["constraints"] = nullptr;
    j["free_functions"] = nullptr;
  }
  j["sga_not_run"] = r.sga || r.sgaNote.empty() ? nlohmann::json(nullptr)
                                                : nlohmann::json(r.sgaNote);
  j["linear"] = r.linear ? linearJson(*r.linear) : nlohmann::json(nullptr);
  return j;
}

} // namespace ldae::passes
