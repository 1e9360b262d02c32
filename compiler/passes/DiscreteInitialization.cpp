// The discrete part of the initialization (DiscreteInitialization.h).
#include "passes/DiscreteInitialization.h"

#include "passes/Events.h"
#include "passes/PassContext.h"

#include "graph/Matching.h"
#include "graph/Scc.h"
#include "ir/Query.h"
#include "ir/Substitute.h"

#include <map>

namespace ldae::passes {

bool solveDiscreteInitialization(PassContext &pc, const EventResult &ev,
                                 std::span<const DiscreteInitSlot> slots,
                                 std::span<const ir::Equation> equations,
                                 std::vector<ir::ExprRef> &preValue) {
  ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  const size_t K = slots.size();
  preValue.assign(K, nullptr);
  if (equations.empty())
    return true;

  // The first round of the initial event: initial() has risen (its pre()
  // is 0), no sample or terminal() fires, a fixed pre() is its start.
  ir::Substitution first(ctx);
  std::map<ir::VarId, size_t> slotOfVar;
  for (size_t k = 0; k < K; ++k) {
    ir::ExprRef cur = ctx.param(ev.current(k)), pre = ctx.param(ev.pre(k));
    switch (slots[k].kind) {
    case ir::DiscreteKind::Initial:
      first.set(cur, ctx.one());
      first.set(pre, ctx.constant(0.0));
      break;
    case ir::DiscreteKind::Sample:
    case ir::DiscreteKind::Terminal:
      first.set(cur, ctx.constant(0.0));
      first.set(pre, ctx.constant(0.0));
      break;
    case ir::DiscreteKind::Variable:
      slotOfVar[slots[k].var] = k;
      if (slots[k].fixed)
        first.set(pre, ctx.constant(ev.discrete[k].start));
      break;
    default:
      break;
    }
  }
  // A discrete variable as that round computes it; pre(v) as the unknown,
  // stood for by v's own Variable node, which no update reads (they read
  // slots), so that solveLinear can solve for it.
  ir::Substitution asUnknowns(ctx), inEquation(ctx);
  for (size_t k = 0; k < K; ++k) {
    if (slots[k].kind != ir::DiscreteKind::Variable)
      continue;
    ir::ExprRef v = ctx.var(slots[k].var);
    ir::ExprRef value = first.apply(ev.update[k]);
    if (!slots[k].fixed)
      asUnknowns.set(ctx.param(ev.pre(k)), v);
    inEquation.set(v, value);
    inEquation.set(ctx.pre(slots[k].var),
                   slots[k].fixed ? ctx.constant(ev.discrete[k].start)
                                  : ctx.param(ev.pre(k)));
  }
  auto isUnknown = [&](ir::VarId v) {
    auto it = slotOfVar.find(v);
    return it != slotOfVar.end() && !slots[it->second].fixed;
  };

  // Each equation over the unknowns; the pre() values it is linear in.
  const size_t E = equations.size();
  std::vector<ir::ExprRef> residual(E);
  std::vector<ir::VarId> unknowns;
  std::map<ir::VarId, int> column;
  std::vector<std::map<int, ir::ExprRef>> solved(E);
  std::vector<std::vector<ir::VarId>> reads(E);
  bool ok = true;
  for (size_t e = 0; e < E; ++e) {
    residual[e] = asUnknowns.apply(inEquation.apply(equations[e].residual));
    for (ir::ParamId p : ir::freeParameters(residual[e]))
      if (p >= ev.base && p < ev.pre(0) &&
          slots[p - ev.base].kind != ir::DiscreteKind::Relation) {
        // A current value the inlining kept (a when-cycle): not a value
        // of the first round.
        pc.diags.report(DiagId::ErrInitialPreSystem, equations[e].loc,
                        {equations[e].text,
                         "it reads '" + ev.discrete[p - ev.base].name +
                             "' through a cycle of when-clauses"});
        ok = false;
      }
    for (ir::VarKey key : ir::freeVariables(residual[e])) {
      if (key.order != 0 || !isUnknown(key.var))
        continue;
      reads[e].push_back(key.var);
      auto [it, fresh] =
          column.emplace(key.var, static_cast<int>(unknowns.size()));
      if (fresh)
        unknowns.push_back(key.var);
      if (ir::ExprRef value = ir::solveLinear(ctx, residual[e], key.var))
        solved[e][it->second] = value;
    }
  }
  if (!ok)
    return false;
  graph::BipartiteGraph g(static_cast<int>(E), static_cast<int>(unknowns.size()));
  for (size_t e = 0; e < E; ++e)
    for (const auto &[col, value] : solved[e])
      g.rows[e].push_back(col);
  graph::Matching mt = graph::maximumMatching(g);
  auto names = [&](const std::vector<ir::VarId> &vars) {
    std::vector<std::string> out;
    for (ir::VarId v : vars)
      out.push_back("pre(" + m.variables[v].name + ")");
    return quotedList(out);
  };
  for (size_t e = 0; e < E; ++e) {
    if (mt.rowMate[e] >= 0)
      continue;
    std::string why =
        reads[e].empty()
            ? "it reads no pre() value that is free (each is fixed or given "
              "by another initial equation)"
        : g.rows[e].empty()
            ? "it is not linear in " + names(reads[e]) +
                  ", and only linear equations of pre() values are solved"
            : "the pre() values it could give, " + names(reads[e]) +
                  ", are given by other initial equations";
    pc.diags.report(DiagId::ErrInitialPreSystem, equations[e].loc,
                    {equations[e].text, why});
    ok = false;
  }
  if (!ok)
    return false;

  // Dependency order: an equation's solution may read the pre() values
  // other equations give. A block of several is a linear system of them.
  graph::BipartiteGraph dependsOn(static_cast<int>(E),
                                  static_cast<int>(unknowns.size()));
  for (size_t e = 0; e < E; ++e)
    for (ir::VarId v : reads[e])
      dependsOn.rows[e].push_back(column[v]);
  std::vector<size_t> order;
  for (const std::vector<int> &block : graph::bltBlocks(dependsOn, mt)) {
    if (block.size() > 1) {
      std::string text;
      for (int e : block)
        text += (text.empty() ? "'" : ", '") + equations[e].text + "'";
      pc.diags.report(DiagId::ErrInitialPreCycle, equations[block[0]].loc,
                      {text});
      return false;
    }
    order.push_back(static_cast<size_t>(block[0]));
  }

  // Inline in that order; a pre() value no equation gives reads its start,
  // as the first round does. Every unknown is then replaced: the values
  // read only continuous unknowns, time and parameters.
  ir::Substitution given(ctx);
  for (size_t j = 0; j < unknowns.size(); ++j)
    if (mt.colMate[j] < 0)
      given.set(ctx.var(unknowns[j]),
                ctx.constant(ev.discrete[slotOfVar[unknowns[j]]].start));
  for (size_t e : order) {
    ir::VarId v = unknowns[static_cast<size_t>(mt.rowMate[e])];
    ir::ExprRef value = given.apply(solved[e][mt.rowMate[e]]);
    given.set(ctx.var(v), value);
    preValue[slotOfVar[v]] = value;
  }
  return true;
}

} // namespace ldae::passes
