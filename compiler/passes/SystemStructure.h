// Incidence of a DaeSystem's residuals in what an index-1 solver solves
// for: y[i] of an algebraic unknown, y'[i] of a differential one (a
// differential unknown's own value is known from integration). Shared by
// the "blt", "prune" and "init" passes.
#pragma once

#include "graph/BipartiteGraph.h"
#include "ir/DaeSystem.h"

#include <map>
#include <vector>

namespace ldae::passes {

/// Where a Variable node is read from under the layout rule.
struct SlotRead {
  int unknown = -1;
  bool derivative = false; // reads y'[unknown]
};

/// Maps Variable nodes to the slots they read in state set `set`.
class SystemLayout {
public:
  SystemLayout(const ir::DaeSystem &sys, size_t set);
  /// -1 unknown when the node is not part of the layout (a parameter-like
  /// discrete variable).
  SlotRead read(ir::VarKey key) const;

private:
  std::map<ir::VarKey, int> slot_;
  std::map<ir::VarKey, int> derivative_;
};

/// Rows: residuals of set `set`; columns: unknowns. With `solved` only the
/// entries an index-1 solver solves for (see above); otherwise every slot
/// read (y or y').
graph::BipartiteGraph systemGraph(const ir::DaeSystem &sys, size_t set,
                                  bool solved);

} // namespace ldae::passes
