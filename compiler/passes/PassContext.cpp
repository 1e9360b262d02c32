// Helpers shared by the passes: locations and texts for messages, and the
// start point at which value-dependent choices are made.
#include "passes/PassContext.h"
#include "ir/External.h"
#include "ir/Query.h"
#include "passes/Events.h"

#include "ir/Print.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace ldae::passes {

const std::vector<int> &PassContext::nameRanks() {
  const std::vector<ir::Variable> &vars = model.variables;
  if (nameRank_.size() == vars.size())
    return nameRank_; // variables are only ever appended, never renamed
  // The first eight bytes of each name as a big-endian number (zero
  // padded) order like the names themselves, and decide most comparisons
  // without reading the strings.
  std::vector<uint64_t> prefix(vars.size(), 0);
  for (size_t v = 0; v < vars.size(); ++v) {
    const std::string &n = vars[v].name;
    for (size_t i = 0; i < 8; ++i)
      prefix[v] = prefix[v] << 8 |
                  (i < n.size() ? static_cast<unsigned char>(n[i]) : 0u);
  }
  std::vector<ir::VarId> byName(vars.size());
  std::iota(byName.begin(), byName.end(), 0);
  std::sort(byName.begin(), byName.end(), [&](ir::VarId a, ir::VarId b) {
    if (prefix[a] != prefix[b])
      return prefix[a] < prefix[b];
    return vars[a].name < vars[b].name;
  });
  nameRank_.assign(vars.size(), 0);
  for (size_t i = 1; i < byName.size(); ++i)
    nameRank_[byName[i]] = vars[byName[i]].name == vars[byName[i - 1]].name
                               ? nameRank_[byName[i - 1]]
                               : static_cast<int>(i);
  return nameRank_;
}

std::string PassContext::where(SourceLoc loc) const {
  if (!loc.valid())
    return "";
  // Diagnostics print the path as given; equations point into the same file.
  return diags.sources().path(loc.file) + ":" + std::to_string(loc.line);
}

std::string PassContext::equationText(int e) const {
  const ir::Equation &eq = model.equations[e];
  if (!eq.text.empty())
    return eq.text;
  return ir::printLsd(eq.residual, &model) + " = 0";
}

ir::EvalEnv PassContext::startEnv() const {
  ir::EvalEnv env;
  const ir::Model *m = &model;
  env.variable = [m](ir::VarKey k) {
    if (k.order != 0 || k.var >= m->variables.size())
      return 0.0;
    return m->variables[k.var].start;
  };
  std::vector<double> params = model.parameterValues();
  env.parameter = [params](ir::ParamId p) {
    return p < params.size() ? params[p] : 0.0;
  };
  return env;
}

ir::EvalEnv PassContext::initializationEnv() const {
  ir::EvalEnv env = startEnv();
  // A mode compiled during a run is not started: its C code (the tables)
  // holds the run's state, which calls at the start time would reset.
  if (!events || events->update.size() != events->discrete.size() ||
      !opts.modeValues.empty())
    return env;
  // Computed once: the C code the update calls (a table's
  // getNextTimeEvent) is called once.
  if (!primedDone_) {
    primedDone_ = true;
    std::vector<double> at = model.parameterValues();
    for (size_t k = 0; k < events->discrete.size(); ++k)
      if (events->discrete[k].kind == ir::DiscreteKind::Initial &&
          events->current(k) < at.size())
        at[events->current(k)] = 1;
    ir::EvalEnv initial = env;
    initial.parameter = [&at](ir::ParamId p) {
      return p < at.size() ? at[p] : 0.0;
    };
    for (size_t k = 0; k < events->discrete.size(); ++k)
      if (events->discrete[k].kind == ir::DiscreteKind::Variable)
        if (Expected<double> v = ir::evaluate(events->update[k], initial);
            v && std::isfinite(*v))
          primed_.emplace_back(events->current(k), *v);
  }
  std::vector<double> params = model.parameterValues();
  for (const auto &[p, v] : primed_)
    if (p < params.size())
      params[p] = v;
  env.parameter = [params](ir::ParamId p) {
    return p < params.size() ? params[p] : 0.0;
  };
  return env;
}

/// The name of an external function an equation calls with arguments
/// that read the unknowns or time, "" if none.
std::string externalOfUnknowns(const ir::Model &m) {
  for (const ir::Equation &eq : m.equations)
    for (ir::ExprRef n : ir::topologicalOrder({&eq.residual, 1}))
      if (n->kind() == ir::ExprKind::External &&
          (!ir::freeVariables(n).empty() || ir::dependsOnTime(n)))
        return ir::externalFunction(n->externalId()).name;
  return "";
}

std::string quotedList(const std::vector<std::string> &items) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0)
      out += i + 1 == items.size() ? " and " : ", ";
    out += quoted(items[i]);
  }
  return out;
}

std::string quotedFew(const std::vector<std::string> &items, size_t total) {
  constexpr size_t kMaxNamed = 8;
  if (total == 0)
    total = items.size();
  size_t shown = std::min(items.size(), kMaxNamed);
  std::string text = quotedList({items.begin(), items.begin() + shown});
  if (total > shown)
    text += " (and " + std::to_string(total - shown) + " more)";
  return text;
}

} // namespace ldae::passes
