// The code plan's utilities that lowering and loop rolling share and that
// only the LLVM-free library needs (PlanRules.cpp holds those the JIT module
// needs too). Nothing here lowers: see PlanLowering.cpp.
#include "codegen/CodePlan.h"

#include "ldae/model.h"
#include "support/SourceManager.h"

namespace ldae::codegen {

bool useDenseJacobian(unsigned n) { return n <= LDAE_DENSE_THRESHOLD; }

void removeDeadNodes(PlanFunction &fn) {
  std::vector<char> live(fn.nodes.size(), 0);
  for (const PlanStore &s : fn.stores)
    live[s.node] = 1;
  for (size_t k = fn.nodes.size(); k-- > 0;) {
    if (!live[k] || isLeaf(fn.nodes[k].op))
      continue;
    const PlanNode &n = fn.nodes[k];
    for (unsigned i = 0; i < numOperands(n.op); ++i)
      live[n.operand(i)] = 1;
  }
  std::vector<uint32_t> newIndex(fn.nodes.size(), 0);
  std::vector<PlanNode> kept;
  for (size_t k = 0; k < fn.nodes.size(); ++k) {
    if (!live[k])
      continue;
    PlanNode n = fn.nodes[k];
    n.a = newIndex[n.a];
    n.b = newIndex[n.b];
    n.c = newIndex[n.c];
    newIndex[k] = kept.size();
    kept.push_back(n);
  }
  fn.nodes = std::move(kept);
  for (PlanStore &s : fn.stores)
    s.node = newIndex[s.node];
}

std::string sourceOrigin(const SourceManager *sources, const SourceLoc &loc,
                         const char *none) {
  if (!sources || !loc.valid())
    return none;
  return sources->path(loc.file) + ":" + std::to_string(loc.line) + ":" +
         std::to_string(loc.col);
}

} // namespace ldae::codegen
