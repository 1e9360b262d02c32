// Pass "build-system": builds the ir::DaeSystem from the augmented
// equations and the dummy choices, following the layout rule of
// ir/DaeSystem.h. (For `--method raw` the rows are the model's own
// equations and no order is a dummy: the system as written.)
//
// For an unknown x whose highest order is d, the slots (unknowns) are x
// itself and each order k in 1..d that is an intermediate order (k < d,
// so that the system is first order: y holds x and der(x) for a model
// written with der(der(x))) or a dummy derivative in some state set. An
// order that is a dummy in every set keeps its own node Variable(x, k) as
// the header describes; any other slot of order k >= 1 gets a fresh model
// variable (named `der(x)`) so that no Variable node can be read both as a
// y and as a y' entry. Where such an order is not a dummy, a link residual
// `der(previous slot) - slot` ties it to its derivative.
//
// A block chosen at run time (DummyChoices::dynamic) adds its states
// s = A c as unknowns of their own, differential in every set, with the
// rows s - A c and der(s) - A der(c); A reads parameters past the discrete
// values' (ir::DynamicStateSet).
#include "passes/Events.h"
#include "passes/JumpPencil.h"
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "ir/Query.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <set>
#include <unordered_map>

namespace ldae::passes {

namespace {

/// The slots of one unknown.
struct Slots {
  std::vector<unsigned> orders; // ascending, starting with 0
  std::vector<ir::VarKey> keys; // the node each slot holds
  std::vector<bool> fresh;
};

} // namespace

namespace {

/// The target and sign of an alias's value `x` or `-x` (x a variable);
/// nothing for any other value (`a = b + 1`, `a = p`).
std::optional<std::pair<ir::VarId, int>> aliasTarget(ir::ExprRef e) {
  if (e->kind() == ir::ExprKind::Variable && e->order() == 0)
    return std::make_pair(e->var(), 1);
  if (e->kind() == ir::ExprKind::Mul && e->numOperands() == 2 &&
      e->operand(0)->isConstant(-1) &&
      e->operand(1)->kind() == ir::ExprKind::Variable &&
      e->operand(1)->order() == 0)
    return std::make_pair(e->operand(1)->var(), -1);
  return std::nullopt;
}

} // namespace

bool buildOutputs(PassContext &pc, const AliasResult &alias,
                  const MatchingResult &mr, VarSubstitution &subst,
                  std::vector<ir::SystemOutput> &out) {
  ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  const size_t userVars = alias.eliminated.size();
  // Outputs in model order (declaration order, array elements by index):
  // every user variable (aliases included) and der(x) right after x where
  // the model differentiates x.
  std::vector<ir::SystemOutput> outputs;
  std::vector<ir::ExprRef> aliasValue(userVars, nullptr);
  for (const Alias &a : alias.aliases)
    aliasValue[a.var] = a.value;
  // Per output, the variable its alias value names with sign (0: none).
  std::vector<std::pair<ir::VarId, int>> aliasOf;
  std::unordered_map<std::string, size_t> ownValue; // name -> output
  for (ir::VarId v = 0; v < userVars; ++v) {
    const ir::Variable &var = m.variables[v];
    auto add = [&](std::string name, ir::ExprRef value, ir::OutputKind kind) {
      ir::SystemOutput o{std::move(name), value};
      o.kind = kind;
      if (kind != ir::OutputKind::Derivative) {
        o.unit = var.unit;
        o.description = var.description;
      }
      outputs.push_back(std::move(o));
      aliasOf.push_back({0, 0});
    };
    if (aliasValue[v]) {
      add(var.name, subst.apply(aliasValue[v]),
          var.isDiscrete ? ir::OutputKind::Discrete
                         : ir::OutputKind::Continuous);
      if (auto t = aliasTarget(aliasValue[v]))
        aliasOf.back() = *t;
    } else if (var.isDiscrete) {
      // A discrete variable is read from its slot of the discrete state.
      std::optional<ir::ParamId> p = m.findParameter(var.name);
      if (var.input == ir::EventInput::None && !var.generated && p &&
          m.parameters[*p].discrete)
        add(var.name, ctx.param(*p), ir::OutputKind::Discrete);
    } else if (mr.unknownIndex[v] >= 0) {
      ownValue[var.name] = outputs.size();
      add(var.name, ctx.var(v), ir::OutputKind::Continuous);
      int j = mr.unknownIndex[v];
      if (mr.originalOrder[j] >= 1)
        add(m.variableName(ir::VarKey{v, 1}), subst.apply(ctx.var(v, 1)),
            ir::OutputKind::Derivative);
    }
  }
  std::vector<size_t> picked;
  if (pc.opts.outputs.empty()) {
    for (size_t k = 0; k < outputs.size(); ++k)
      picked.push_back(k);
  } else {
    std::unordered_map<std::string, size_t> byName;
    for (size_t k = 0; k < outputs.size(); ++k)
      byName[outputs[k].name] = k;
    for (const std::string &name : pc.opts.outputs) {
      if (auto it = byName.find(name); it != byName.end())
        picked.push_back(it->second);
      // A parameter is a constant column the runtime reports itself.
      else if (std::optional<ir::ParamId> p = m.findParameter(name);
               !p || m.parameters[*p].discrete)
        pc.diags.report(DiagId::ErrUnknownOutput, SourceLoc{}, {name});
    }
    if (pc.diags.hasErrors())
      return false;
  }
  std::unordered_map<size_t, int> position; // output -> index in `out`
  for (size_t i = 0; i < picked.size(); ++i)
    position.emplace(picked[i], static_cast<int>(i));
  for (size_t k : picked) {
    out.push_back(outputs[k]);
    auto [target, sign] = aliasOf[k];
    if (!sign)
      continue;
    auto own = ownValue.find(m.variables[target].name);
    if (own == ownValue.end())
      continue;
    if (auto at = position.find(own->second); at != position.end())
      out.back().alias = sign * (at->second + 1);
  }
  return true;
}

namespace {

/// The states, rows and tables of the blocks chosen at run time: per block
/// and state k, the unknown s_k (start value A c at the start), the rows
/// s_k - sum_j A_kj c_j and der(s_k) - sum_j A_kj der(c_j) appended to
/// `common`, and the block's Jacobian and candidate values for the runtime.
void addDynamicSets(PassContext &pc, const EventResult &ev,
                    const DummyChoices &dc, VarSubstitution &subst,
                    ir::DaeSystem &sys, std::vector<ir::ExprRef> &common) {
  if (dc.dynamic.empty())
    return;
  ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  ir::EvalEnv env = pc.startEnv();
  // p holds the user's parameters, the discrete values and their pre()
  // values; the selection matrices follow. The model's parameter list
  // gets entries up to there so that names print and start values read.
  const size_t nd = ev.discrete.size();
  const size_t base = m.userParameterCount() + 2 * nd;
  auto setParam = [&](size_t id, std::string name, double value) {
    while (m.parameters.size() <= id) {
      ir::Parameter p;
      p.discrete = true;
      m.parameters.push_back(p);
    }
    ir::Parameter &p = m.parameters[id];
    p.name = std::move(name);
    p.value = value;
    p.discrete = true;
  };
  for (size_t k = m.userParameterCount() + nd; k < base; ++k)
    setParam(k, "pre(" + m.parameters[k - nd].name + ")",
             m.parameters[k - nd].value);
  size_t next = base;
  for (size_t b = 0; b < dc.dynamic.size(); ++b) {
    const DynamicBlock &blk = dc.dynamic[b];
    ir::DynamicStateSet ds;
    ds.rows = blk.rows;
    ds.forced = static_cast<unsigned>(blk.forced.size());
    ds.candidates = static_cast<unsigned>(blk.candidates.size());
    const unsigned ns = ds.candidates + ds.forced - ds.rows;
    const std::string set = "$stateset" + std::to_string(b + 1);
    for (ir::ExprRef e : blk.jacobian)
      ds.jacobian.push_back(subst.apply(e));
    std::vector<ir::ExprRef> c, dcs;
    for (ir::VarKey k : blk.candidates) {
      c.push_back(subst.apply(ctx.var(k.var, k.order)));
      dcs.push_back(subst.apply(ctx.var(k.var, k.order + 1)));
      ds.names.push_back(m.variableName(k));
    }
    ds.values = c;
    ds.values.insert(ds.values.end(), dcs.begin(), dcs.end());
    // The start's states: the candidates the start's pivoting left.
    std::vector<int> states;
    for (int j = 0; j < static_cast<int>(ds.candidates); ++j)
      if (!std::binary_search(blk.startDummies.begin(), blk.startDummies.end(),
                              j))
        states.push_back(j);
    ds.param = static_cast<ir::ParamId>(next);
    ds.start.assign(size_t(ns) * ds.candidates, 0.0);
    for (unsigned k = 0; k < ns && k < states.size(); ++k)
      ds.start[k + size_t(ns) * states[k]] = 1;
    for (unsigned j = 0; j < ds.candidates; ++j)
      for (unsigned k = 0; k < ns; ++k)
        setParam(next++,
                 set + ".A[" + std::to_string(k + 1) + "," +
                     std::to_string(j + 1) + "]",
                 ds.start[k + size_t(ns) * j]);
    for (unsigned k = 0; k < ns; ++k) {
      ir::Variable v;
      v.name = set + ".x[" + std::to_string(k + 1) + "]";
      v.loc = m.loc;
      ir::VarId sv = m.addVariable(v);
      std::vector<ir::ExprRef> value, slope;
      double start = 0;
      for (unsigned j = 0; j < ds.candidates; ++j) {
        ir::ExprRef a = ctx.param(ds.param + k + ns * j);
        value.push_back(ctx.mul(a, c[j]));
        slope.push_back(ctx.mul(a, dcs[j]));
        if (ds.start[k + size_t(ns) * j] != 0)
          if (auto s0 = ir::evaluate(c[j], env))
            start += *s0;
      }
      common.push_back(ctx.sub(ctx.var(sv, 0), ctx.add(value)));
      common.push_back(ctx.sub(ctx.var(sv, 1), ctx.add(slope)));
      sys.residualLocs.push_back(m.loc);
      sys.residualLocs.push_back(m.loc);
      ir::SystemUnknown u;
      u.key = {sv, 0};
      u.name = v.name;
      u.start = start;
      u.loc = m.loc;
      sys.unknowns.push_back(u);
      ds.states.push_back(u.key);
    }
    sys.dynamicSets.push_back(std::move(ds));
  }
  sys.selectionCount = static_cast<unsigned>(next - base);
}

class BuildSystemPass
    : public TypedPass<BuildSystemPass,
                       Reads<EventResult, AliasResult, MatchingResult,
                             IndexReduction, DummyChoices>,
                       Updates<>, Produces<ir::DaeSystem>> {
public:
  BuildSystemPass() : TypedPass(PassId::BuildSystem) {}
  bool runOn(PassContext &pc, const EventResult &ev, const AliasResult &alias,
             const MatchingResult &mr, const IndexReduction &red,
             const DummyChoices &dc, ir::DaeSystem &out);
};

bool BuildSystemPass::runOn(PassContext &pc, const EventResult &ev,
                            const AliasResult &alias,
                            const MatchingResult &mr,
                            const IndexReduction &red, const DummyChoices &dc,
                            ir::DaeSystem &out) {
  ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  const size_t nu = mr.unknowns.size();
  const size_t nsets = dc.choices.size();

  ir::DaeSystem sys;
  sys.ctx = m.sharedCtx();
  sys.model = &m;
  sys.index = red.handedIndex;

  VarSubstitution subst(ctx);
  auto set = [&](ir::ExprRef from, ir::ExprRef to) {
    subst.set(from->varKey(), to);
  };
  std::vector<Slots> slots(nu);
  for (size_t j = 0; j < nu; ++j) {
    const ir::VarId v = mr.unknowns[j];
    const ir::Variable var = m.variables[v]; // copy: addVariable may realloc
    const unsigned d = red.highest[j];
    unsigned always = 0, any = d + 1;
    for (const DummyChoice &c : dc.choices) {
      always = std::max<unsigned>(always, c[j]);
      any = std::min<unsigned>(any, c[j]);
    }
    Slots &sl = slots[j];
    for (unsigned k = 0; k <= d; ++k) {
      bool slot = k == 0 || k + 1 <= d || k >= any;
      if (!slot) {
        // The top order read as the derivative of the slot below.
        if (k >= 2)
          set(ctx.var(v, k), ctx.var(sl.keys.back().var, 1));
        continue;
      }
      sl.orders.push_back(k);
      if (k == 0 || k >= always) {
        sl.keys.push_back({v, k});
        sl.fresh.push_back(false);
        continue;
      }
      ir::Variable f;
      f.name = m.variableName(ir::VarKey{v, k});
      f.component = var.component;
      f.loc = var.loc;
      f.nominal = var.nominal;
      f.stateSelect = var.stateSelect;
      ir::VarId fv = m.addVariable(f);
      sl.keys.push_back({fv, 0});
      sl.fresh.push_back(true);
      set(ctx.var(v, k), ctx.var(fv, 0));
    }
  }

  // Unknowns.
  std::vector<std::pair<size_t, size_t>> slotOf; // unknown index -> (j, slot)
  for (size_t j = 0; j < nu; ++j) {
    const ir::Variable &var = m.variables[mr.unknowns[j]];
    for (size_t k = 0; k < slots[j].orders.size(); ++k) {
      ir::SystemUnknown u;
      u.key = slots[j].keys[k];
      u.name = m.variableName(ir::VarKey{mr.unknowns[j], slots[j].orders[k]});
      u.start = slots[j].orders[k] == 0 ? var.start : 0.0;
      u.startBinding = slots[j].orders[k] == 0 ? var.startBinding : nullptr;
      u.nominal = var.nominal;
      u.fixed = slots[j].orders[k] == 0 && var.fixed;
      u.loc = var.loc;
      sys.unknowns.push_back(u);
      slotOf.emplace_back(j, k);
    }
  }

  // Residuals shared by every set: the equations and their derivatives.
  std::vector<ir::ExprRef> common;
  for (size_t i = 0; i < mr.equations.size(); ++i) {
    const ir::Equation &eq = m.equations[mr.equations[i]];
    for (int r = static_cast<int>(i); r >= 0; r = red.rows[r].next) {
      common.push_back(subst.apply(red.rows[r].residual));
      sys.residualLocs.push_back(eq.loc);
    }
    if (red.rows[i].next >= 0)
      sys.constraints.push_back(subst.apply(red.rows[i].residual));
  }
  addDynamicSets(pc, ev, dc, subst, sys, common);
  const size_t n = sys.unknowns.size();

  for (size_t set = 0; set < nsets; ++set) {
    const DummyChoice &choice = dc.choices[set];
    ir::StateSet st;
    st.residuals = common;
    st.differential.assign(n, false);
    for (size_t u = 0; u < n; ++u) {
      if (u >= slotOf.size()) { // a dynamic block's state
        st.differential[u] = true;
        continue;
      }
      auto [j, k] = slotOf[u];
      const Slots &sl = slots[j];
      unsigned order = sl.orders[k];
      unsigned d = red.highest[j];
      st.differential[u] =
          order + 1 <= d && static_cast<int>(order + 1) < choice[j];
      if (sl.fresh[k] && static_cast<int>(order) < choice[j]) {
        ir::VarKey below = sl.keys[k - 1];
        st.residuals.push_back(
            ctx.sub(ctx.var(below.var, below.order + 1), ctx.var(sl.keys[k])));
        if (set == 0)
          sys.residualLocs.push_back(sys.unknowns[u].loc);
      }
    }
    if (st.residuals.size() != n) {
      pc.diags.report(DiagId::ErrIndexReductionFailed, m.loc,
                     {"the reduced system has " +
                      std::to_string(st.residuals.size()) + " equations for " +
                      std::to_string(n) + " unknowns"});
      return false;
    }
    for (size_t u = 0; u < n; ++u) {
      if (st.differential[u])
        st.states.push_back(sys.unknowns[u].name);
    }
    st.pivotSize = dc.pivotSizes[set];
    for (ir::ExprRef e : dc.pivots[set])
      st.pivot.push_back(subst.apply(e));
    StateSetReport rep;
    rep.states = st.states;
    for (size_t u = 0; u < slotOf.size(); ++u) {
      auto [j, k] = slotOf[u];
      if (slots[j].orders[k] >= 1 &&
          static_cast<int>(slots[j].orders[k]) >= choice[j])
        rep.dummies.push_back(sys.unknowns[u].name);
    }
    rep.pivotSize = st.pivotSize;
    for (ir::ExprRef e : st.pivot)
      rep.pivot.push_back(ir::printLsd(e, &m));
    pc.report.stateSets.push_back(rep);
    sys.stateSets.push_back(std::move(st));
  }

  // Differential unknowns are never fixed-free guesses for their
  // derivative; start derivatives stay 0 unless initialization finds more.
  for (const ir::Equation &e : m.initialEquations)
    sys.initialResiduals.push_back(subst.apply(e.residual));

  if (!buildOutputs(pc, alias, mr, subst, sys.outputs))
    return false;

  // The event part reads eliminated aliases through their values.
  ir::Substitution aliasSubst(ctx);
  for (const Alias &a : alias.aliases)
    aliasSubst.set(ctx.var(a.var), a.value);
  if (!fillEvents(
          pc, ev,
          [&](ir::ExprRef e) { return subst.apply(aliasSubst.apply(e)); },
          sys))
    return false;

  pc.report.states = sys.stateSets[0].states;
  pc.report.dummies = pc.report.stateSets[0].dummies;
  pc.report.dof = static_cast<int>(pc.report.states.size());
  pc.report.systemUnknowns = static_cast<int>(n);
  fillJumpPencil(pc, mr, red, dc, sys);
  out = std::move(sys);
  return true;
}

} // namespace

std::unique_ptr<Pass> createBuildSystemPass() {
  return std::make_unique<BuildSystemPass>();
}

} // namespace ldae::passes
