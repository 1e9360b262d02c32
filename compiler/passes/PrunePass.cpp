// Pass "prune": with requested outputs, keeps only the unknowns and
// residuals they depend on: the residual solving each needed unknown (in
// every state set), everything that residual reads, and for a state the
// residual giving its derivative, transitively. What events and the
// run-time state choice (pivots, dynamic state sets) read is kept whatever
// the outputs. The result compiles only what the outputs need.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "ir/Query.h"

namespace ldae::passes {

namespace {

class PrunePass
    : public TypedPass<PrunePass, Reads<>, Updates<ir::DaeSystem, BltResult>,
                       Produces<>> {
public:
  PrunePass() : TypedPass(PassId::Prune) {}
  bool runOn(PassContext &ctx, ir::DaeSystem &sys, BltResult &blt);
};

// The walk needs every unknown matched: --method raw, whose unreduced
// system is singular above index one, does not run this pass.
bool PrunePass::runOn(PassContext &ctx, ir::DaeSystem &sys, BltResult &blt) {
  if (ctx.opts.outputs.empty() || ctx.jumpsMatter ||
      blt.matchings.size() != sys.stateSets.size())
    return true;
  const size_t n = sys.unknowns.size();
  std::vector<char> need(n, 0);
  std::vector<int> queue;
  auto want = [&](int u) {
    if (u >= 0 && !need[u]) {
      need[u] = 1;
      queue.push_back(u);
    }
  };
  SystemLayout layout0(sys, 0);
  for (const ir::SystemOutput &o : sys.outputs)
    for (ir::VarKey k : variablesOf(o.value))
      want(layout0.read(k).unknown);
  // What the events read and the states reinit writes stay: the events
  // happen whatever the outputs.
  std::vector<ir::ExprRef> eventReads = ir::eventExprs(sys.events);
  eventReads.insert(eventReads.end(), sys.roots.begin(), sys.roots.end());
  for (ir::ExprRef e : eventReads)
    for (ir::VarKey k : variablesOf(e))
      want(layout0.read(k).unknown);
  for (const ir::ReinitUpdate &r : sys.events.reinits)
    want(static_cast<int>(r.unknown));
  // What the run-time state choice reads stays too: a state set's pivot
  // (over its own keys), and a dynamic set's states, its Jacobian and its
  // candidates with their derivatives (over set 0's, as code generation
  // reads them), whether or not the outputs need that part of the model.
  // The walk below then keeps the rows that determine them.
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    SystemLayout layout(sys, set);
    for (ir::ExprRef e : sys.stateSets[set].pivot)
      for (ir::VarKey k : variablesOf(e))
        want(layout.read(k).unknown);
  }
  for (const ir::DynamicStateSet &ds : sys.dynamicSets) {
    for (ir::VarKey s : ds.states)
      for (size_t u = 0; u < n; ++u)
        if (sys.unknowns[u].key == s)
          want(static_cast<int>(u));
    for (const std::vector<ir::ExprRef> *es : {&ds.jacobian, &ds.values})
      for (ir::ExprRef e : *es)
        for (ir::VarKey k : variablesOf(e))
          want(layout0.read(k).unknown);
  }
  std::vector<graph::BipartiteGraph> reads;
  for (size_t set = 0; set < sys.stateSets.size(); ++set)
    reads.push_back(systemGraph(sys, set, blt.reads[set], false));
  for (size_t q = 0; q < queue.size(); ++q) {
    int u = queue[q];
    for (size_t set = 0; set < sys.stateSets.size(); ++set) {
      int r = blt.matchings[set].colMate[u];
      if (r < 0)
        continue;
      for (int c : reads[set].rows[r])
        want(c);
    }
  }

  std::vector<int> newIndex(n, -1);
  std::vector<ir::SystemUnknown> unknowns;
  for (size_t u = 0; u < n; ++u)
    if (need[u]) {
      newIndex[u] = static_cast<int>(unknowns.size());
      unknowns.push_back(sys.unknowns[u]);
    }
  std::vector<SourceLoc> locs;
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    ir::StateSet &st = sys.stateSets[set];
    ir::StateSet kept;
    kept.pivotSize = st.pivotSize;
    kept.pivot = st.pivot;
    for (size_t u = 0; u < n; ++u)
      if (need[u]) {
        kept.differential.push_back(st.differential[u]);
        if (!st.keys.empty())
          kept.keys.push_back(st.keys[u]);
      }
    for (size_t r = 0; r < st.residuals.size(); ++r) {
      int u = blt.matchings[set].rowMate[r];
      if (u < 0 || !need[u])
        continue;
      kept.residuals.push_back(st.residuals[r]);
      if (set == 0)
        locs.push_back(sys.residualLocs[r]);
    }
    for (size_t u = 0; u < n; ++u)
      if (need[u] && st.differential[u])
        kept.states.push_back(sys.unknowns[u].name);
    st = std::move(kept);
  }
  // Constraints and initial conditions that read pruned unknowns go too.
  auto keepsOnly = [&](ir::ExprRef e) {
    for (ir::VarKey k : variablesOf(e)) {
      SlotRead sr = layout0.read(k);
      if (sr.unknown >= 0 && !need[sr.unknown])
        return false;
    }
    return true;
  };
  std::erase_if(sys.constraints, [&](ir::ExprRef e) { return !keepsOnly(e); });
  std::erase_if(sys.initialResiduals,
                [&](ir::ExprRef e) { return !keepsOnly(e); });
  if (!ir::renumberReinits(sys.events, newIndex))
    return false;
  ctx.report.prunedUnknowns = static_cast<int>(n - unknowns.size());
  sys.unknowns = std::move(unknowns);
  sys.residualLocs = std::move(locs);
  ctx.report.systemUnknowns = static_cast<int>(sys.unknowns.size());
  // Matchings refer to the old numbering: order again for later passes.
  return bltOrder(ctx, sys, false, blt);
}

} // namespace

std::unique_ptr<Pass> createPrunePass() {
  return std::make_unique<PrunePass>();
}

} // namespace ldae::passes
