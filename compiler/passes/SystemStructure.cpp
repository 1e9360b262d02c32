#include "passes/SystemStructure.h"

#include "ir/Query.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <unordered_set>

namespace ldae::passes {

std::vector<ir::VarKey> variablesOf(ir::ExprRef e) {
  std::vector<ir::VarKey> out;
  // Reused buffers: this runs once per residual, many times per pass.
  thread_local std::vector<ir::ExprRef> stack, seenSmall;
  thread_local std::unordered_set<ir::ExprRef> seen;
  stack.assign(1, e);
  seenSmall.clear();
  if (!seen.empty()) // clear() would wipe every bucket, even when empty
    seen.clear();
  auto visited = [&](ir::ExprRef n) {
    if (seen.empty()) {
      if (std::find(seenSmall.begin(), seenSmall.end(), n) != seenSmall.end())
        return true;
      seenSmall.push_back(n);
      if (seenSmall.size() > 32)
        seen.insert(seenSmall.begin(), seenSmall.end());
      return false;
    }
    return !seen.insert(n).second;
  };
  while (!stack.empty()) {
    ir::ExprRef n = stack.back();
    stack.pop_back();
    if (n->numOperands() == 0) {
      if (n->kind() == ir::ExprKind::Variable)
        out.push_back(n->varKey());
      continue;
    }
    if (visited(n))
      continue;
    for (ir::ExprRef op : n->operands())
      stack.push_back(op);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void VarSubstitution::set(ir::VarKey from, ir::ExprRef to) {
  map_[code(from)] = to;
  memo_.clear();
}

ir::ExprRef VarSubstitution::apply(ir::ExprRef root) {
  if (map_.empty())
    return root;
  auto known = [&](ir::ExprRef n) -> ir::ExprRef & {
    if (n->id() >= memo_.size())
      memo_.resize(std::max<size_t>(n->id() + 1, 2 * memo_.size()), nullptr);
    return memo_[n->id()];
  };
  struct Frame {
    ir::ExprRef node;
    bool expanded;
  };
  std::vector<Frame> stack{{root, false}};
  std::vector<ir::ExprRef> ops;
  while (!stack.empty()) {
    Frame f = stack.back();
    stack.pop_back();
    ir::ExprRef n = f.node;
    if (known(n))
      continue;
    if (n->numOperands() == 0) {
      ir::ExprRef r = n;
      if (n->kind() == ir::ExprKind::Variable)
        if (auto it = map_.find(code(n->varKey())); it != map_.end())
          r = it->second;
      known(n) = r;
      continue;
    }
    if (!f.expanded) {
      stack.push_back({n, true});
      for (ir::ExprRef op : n->operands())
        if (!known(op))
          stack.push_back({op, false});
      continue;
    }
    ops.clear();
    bool changed = false;
    for (ir::ExprRef op : n->operands()) {
      ops.push_back(known(op));
      changed = changed || ops.back() != op;
    }
    ir::ExprRef r = changed ? ir::rebuild(ctx_, n, ops) : n;
    known(n) = r;
  }
  return known(root);
}

SystemLayout::SystemLayout(const ir::DaeSystem &sys, size_t set) {
  slot_.reserve(sys.unknowns.size());
  derivative_.reserve(sys.unknowns.size());
  const ir::StateSet &st = sys.stateSets[set];
  for (size_t u = 0; u < sys.unknowns.size(); ++u) {
    ir::VarKey k = sys.unknowns[u].key;
    slot_[code(k)] = static_cast<int>(u);
    if (st.differential[u])
      derivative_[code({k.var, k.order + 1})] = static_cast<int>(u);
  }
}

SlotRead SystemLayout::read(ir::VarKey key) const {
  if (auto it = slot_.find(code(key)); it != slot_.end())
    return {it->second, false};
  if (auto it = derivative_.find(code(key)); it != derivative_.end())
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
    for (ir::VarKey k : variablesOf(st.residuals[r])) {
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
