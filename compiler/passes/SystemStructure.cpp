#include "passes/SystemStructure.h"

#include "ir/Query.h"

#include <algorithm>

namespace ldae::passes {

SystemLayout::SystemLayout(const ir::DaeSystem &sys, size_t set) {
  const ir::StateSet &st = sys.stateSets[set];
  for (size_t u = 0; u < sys.unknowns.size(); ++u) {
    ir::VarKey k = sys.unknowns[u].key;
    slot_[k] = static_cast<int>(u);
    if (st.differential[u])
      derivative_[{k.var, k.order + 1}] = static_cast<int>(u);
  }
}

SlotRead SystemLayout::read(ir::VarKey key) const {
  if (auto it = slot_.find(key); it != slot_.end())
    return {it->second, false};
  if (auto it = derivative_.find(key); it != derivative_.end())
    return {it->second, true};
  return {};
}

graph::BipartiteGraph systemGraph(const ir::DaeSystem &sys, size_t set,
                                  bool solved) {
  const ir::StateSet &st = sys.stateSets[set];
  SystemLayout layout(sys, set);
  graph::BipartiteGraph g(static_cast<int>(st.residuals.size()),
                          static_cast<int>(sys.unknowns.size()));
  for (size_t r = 0; r < st.residuals.size(); ++r) {
    std::vector<int> &row = g.rows[r];
    for (ir::VarKey k : ir::freeVariables(st.residuals[r])) {
      SlotRead sr = layout.read(k);
      if (sr.unknown < 0)
        continue;
      if (solved && st.differential[sr.unknown] && !sr.derivative)
        continue; // a state: known to the solver
      row.push_back(sr.unknown);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  return g;
}

} // namespace ldae::passes
