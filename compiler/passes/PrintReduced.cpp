// `--emit reduced`: the index-1 system as a model lsd can read back. Dummy
// derivatives and the first-order unknowns become ordinary variables with
// identifier names (`der(x)` prints as `der_x`), so the printed model has
// the reduced model's meaning; residuals are printed as `0 = r`.
#include "passes/Pipeline.h"

#include "ir/MessageText.h"
#include "ir/Print.h"
#include "ir/Substitute.h"

#include <map>
#include <set>
#include <sstream>

namespace ldae::passes {

namespace {

std::string identifier(const std::string &name) {
  std::string out;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_')
      out += c;
    else if (c == '.' || c == '[' || c == ',' || c == '(')
      out += '_';
  }
  while (!out.empty() && out.back() == '_')
    out.pop_back();
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0])))
    out = "v_" + out;
  return out;
}

/// Names printed variables (`VarId`s of the model, plus ids past its end
/// for the dummy derivatives) and parameters by identifier.
class Names : public ir::NameResolver {
public:
  std::map<ir::VarId, std::string> vars;
  std::vector<std::string> params;
  std::string variableName(ir::VarId v) const override {
    auto it = vars.find(v);
    return it == vars.end() ? "v" + std::to_string(v) : it->second;
  }
  std::string parameterName(ir::ParamId p) const override {
    return p < params.size() ? params[p] : "p" + std::to_string(p);
  }
};

/// The event part as comments: roots, time events, the update and the
/// reinits, over the printed names.
void printEvents(const ir::DaeSystem &sys, ir::Substitution &subst,
                 const Names &names, std::ostream &out) {
  const ir::EventSystem &ev = sys.events;
  if (ev.empty())
    return;
  auto lsd = [&](ir::ExprRef e) {
    return ir::printLsd(subst.apply(e), &names);
  };
  out << "  // events:\n";
  for (size_t j = 0; j < sys.roots.size(); ++j)
    out << "  //   root " << lsd(sys.roots[j]) << " switches '"
        << ev.discrete[ev.rootRelation[j]].name << "'\n";
  for (size_t j = 0; j < ev.timeThresholds.size(); ++j)
    out << "  //   time event at " << lsd(ev.timeThresholds[j])
        << " switches '" << ev.discrete[ev.thresholdRelation[j]].name
        << "'\n";
  for (size_t j = 0; j < ev.samples.size(); ++j)
    out << "  //   sample from " << lsd(ev.samples[j].first) << " every "
        << lsd(ev.samples[j].second) << "\n";
  for (const ir::DelayInput &d : ev.delays)
    out << "  //   delay '" << ev.discrete[d.discrete].name << "' of "
        << lsd(d.source) << " by " << lsd(d.time) << " (at most "
        << lsd(d.max) << ")\n";
  for (size_t k = 0; k < ev.update.size(); ++k)
    out << "  //   update '" << ev.discrete[k].name
        << "' := " << lsd(ev.update[k]) << "\n";
  for (const ir::ReinitUpdate &r : ev.reinits)
    out << "  //   reinit " << sys.unknowns[r.unknown].name << " := "
        << lsd(r.value) << " where " << lsd(r.fired) << "\n";
  for (const ir::TerminateUpdate &t : ev.terminates)
    out << "  //   terminate \"" << t.message << "\" where " << lsd(t.fired)
        << "\n";
  for (const ir::AssertCheck &a : ev.asserts) {
    std::vector<std::string> values;
    for (ir::ExprRef v : a.messageValues)
      values.push_back(lsd(v));
    out << "  //   assert " << lsd(a.condition) << " "
        << ir::messageExpression(a.message, values)
        << (a.level ? " (warning)" : "") << "\n";
  }
  if (!ev.modeDiscrete.empty()) {
    out << "  //   mode:";
    for (size_t i = 0; i < ev.modeDiscrete.size(); ++i)
      out << " '" << ev.discrete[ev.modeDiscrete[i]].name
          << "' = " << ir::printNumber(ev.modeValues[i]);
    out << "\n";
  }
}

} // namespace

std::string printReduced(const ir::DaeSystem &sys) {
  const ir::Model &m = *sys.model;
  ir::ExprContext &ctx = *sys.ctx;
  Names names;
  std::set<std::string> used;
  auto unique = [&](std::string id) {
    std::string base = id;
    for (int k = 2; used.count(id); ++k)
      id = base + "_" + std::to_string(k);
    used.insert(id);
    return id;
  };
  std::ostringstream out;
  std::string modelName = identifier(m.name.empty() ? "Model" : m.name);
  out << "// index-1 system made by ldaec from '" << m.name << "'\n";
  const ir::StateSet &st = sys.stateSets[0];
  out << "// states:";
  for (const std::string &s : st.states)
    out << " " << s;
  out << "\nmodel " << modelName << "_reduced\n";
  for (size_t p = 0; p < sys.parameterNames.size(); ++p) {
    names.params.push_back(unique(identifier(sys.parameterNames[p])));
    out << "  parameter Real " << names.params.back() << " = "
        << ir::printNumber(p < sys.parameterValues.size()
                               ? sys.parameterValues[p]
                               : 0.0)
        << ";\n";
  }
  // The discrete state, frozen between events: parameters of the
  // continuous system at their start values.
  const size_t nd = sys.events.discrete.size();
  if (nd > 0)
    out << "  // discrete state (frozen between events; pre() values next)\n";
  for (size_t k = 0; k < 2 * nd; ++k) {
    size_t p = sys.parameterNames.size() + k;
    const ir::DiscreteValue &d = sys.events.discrete[k % nd];
    std::string name = k < nd ? d.name : "pre(" + d.name + ")";
    names.params.push_back(p < m.parameters.size() ? m.parameters[p].name
                                                    : name);
    out << "  parameter Real " << ir::printIdentifier(names.params.back())
        << " = " << ir::printNumber(d.start) << ";\n";
  }
  // Every unknown is printed as an order-0 variable; a dummy Variable(x, k)
  // gets a fresh id past the model's variables.
  ir::Substitution subst(ctx);
  ir::VarId next = static_cast<ir::VarId>(m.variables.size());
  std::map<ir::VarId, bool> declared;
  for (size_t u = 0; u < sys.unknowns.size(); ++u) {
    const ir::SystemUnknown &x = sys.unknowns[u];
    std::string id = unique(identifier(x.name));
    ir::VarId v = x.key.var;
    if (x.key.order > 0) {
      v = next++;
      subst.set(ctx.var(x.key), ctx.var(v));
    }
    names.vars[v] = id;
    out << "  Real " << id << "(start = " << ir::printNumber(x.start);
    if (x.fixed)
      out << ", fixed = true";
    if (x.nominal != 1)
      out << ", nominal = " << ir::printNumber(x.nominal);
    out << ")";
    if (id != x.name)
      out << " \"" << x.name << (x.key.order > 0 ? " (dummy derivative)" : "")
          << "\"";
    out << ";\n";
  }
  // Variables read but not unknowns (discrete variables) keep their names.
  for (ir::VarId v = 0; v < m.variables.size(); ++v)
    if (!names.vars.count(v))
      names.vars[v] = identifier(m.variables[v].name);
  out << "equation\n";
  for (ir::ExprRef r : st.residuals)
    out << "  0 = " << ir::printLsd(subst.apply(r), &names) << ";\n";
  if (!sys.initialResiduals.empty()) {
    out << "initial equation\n";
    for (ir::ExprRef r : sys.initialResiduals)
      out << "  0 = " << ir::printLsd(subst.apply(r), &names) << ";\n";
  }
  printEvents(sys, subst, names, out);
  out << "end " << modelName << "_reduced;\n";
  return out.str();
}

} // namespace ldae::passes
