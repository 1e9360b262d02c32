// Incidence of a DaeSystem's residuals in what an index-1 solver solves
// for: y[i] of an algebraic unknown, y'[i] of a differential one (a
// differential unknown's own value is known from integration). Shared by
// the "blt", "prune" and "init" passes.
#pragma once

#include "graph/BipartiteGraph.h"
#include "ir/DaeSystem.h"

#include <unordered_map>
#include <vector>

namespace ldae::passes {

/// The distinct Variable nodes of `e`, sorted: ir::freeVariables for the
/// many small residuals of a model, without a per-call cost in the size of
/// the whole context. Sets `*readsPre` if `e` contains a `pre` node.
std::vector<ir::VarKey> variablesOf(ir::ExprRef e, bool *readsPre = nullptr);

/// Replaces Variable nodes by expressions, memoized by node id in a dense
/// table (one residual after another over a shared DAG, so every node is
/// rebuilt once).
class VarSubstitution {
public:
  explicit VarSubstitution(ir::ExprContext &ctx) : ctx_(ctx) {}
  void set(ir::VarKey from, ir::ExprRef to);
  bool empty() const { return map_.empty(); }
  ir::ExprRef apply(ir::ExprRef e);

private:
  static uint64_t code(ir::VarKey k) {
    return (static_cast<uint64_t>(k.var) << 16) | k.order;
  }
  ir::ExprContext &ctx_;
  std::unordered_map<uint64_t, ir::ExprRef> map_;
  std::vector<ir::ExprRef> memo_; // by node id
};

/// Where a Variable node is read from under the layout rule.
struct SlotRead {
  int unknown = -1;
  bool derivative = false; // reads y'[unknown]
};

/// Maps Variable nodes to the slots they read in state set `set`, by the
/// layout rule (ir::forEachLayoutRead, shared with code generation).
class SystemLayout {
public:
  SystemLayout(const ir::DaeSystem &sys, size_t set);
  /// -1 unknown when the node is not part of the layout (a parameter-like
  /// discrete variable).
  SlotRead read(ir::VarKey key) const;

private:
  static uint64_t code(ir::VarKey k) {
    return (static_cast<uint64_t>(k.var) << 16) | k.order;
  }
  std::unordered_map<uint64_t, SlotRead> reads_;
};

/// For each residual of state set `set`, the slots it reads (sorted).
using SystemReads = std::vector<std::vector<SlotRead>>;
SystemReads systemReads(const ir::DaeSystem &sys, size_t set);

/// Rows: residuals of set `set`; columns: unknowns. With `solved` only the
/// entries an index-1 solver solves for (see above); otherwise every slot
/// read (y or y').
graph::BipartiteGraph systemGraph(const ir::DaeSystem &sys, size_t set,
                                  const SystemReads &reads, bool solved);

} // namespace ldae::passes
