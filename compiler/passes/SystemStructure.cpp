#include "passes/SystemStructure.h"

#include "ir/Query.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <unordered_set>

namespace ldae::passes {

std::vector<ir::VarKey> variablesOf(ir::ExprRef e, bool *readsPre) {
  std::vector<ir::VarKey> out;
  // Visited marks by node id with a generation stamp: no clearing between
  // calls, O(1) per node (this runs once per residual, many times).
  thread_local std::vector<uint32_t> stamp;
  thread_local uint32_t generation = 0;
  thread_local std::vector<ir::ExprRef> stack;
  if (++generation == 0) {
    std::fill(stamp.begin(), stamp.end(), 0);
    generation = 1;
  }
  stack.assign(1, e);
  while (!stack.empty()) {
    ir::ExprRef n = stack.back();
    stack.pop_back();
    if (n->numOperands() == 0) {
      if (n->kind() == ir::ExprKind::Variable)
        out.push_back(n->varKey());
      else if (readsPre && n->kind() == ir::ExprKind::Pre)
        *readsPre = true;
      continue;
    }
    if (n->id() >= stamp.size())
      stamp.resize(std::max<size_t>(n->id() + 1, 2 * stamp.size()), 0);
    if (stamp[n->id()] == generation)
      continue;
    stamp[n->id()] = generation;
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
  reads_.reserve(2 * sys.unknowns.size());
  ir::forEachLayoutRead(sys, sys.stateSets[set].keys,
                        ir::setDifferential(sys, set),
                        [&](ir::VarKey k, uint32_t slot, bool derivative) {
                          reads_.emplace(code(k),
                                         SlotRead{int(slot), derivative});
                        });
}

SlotRead SystemLayout::read(ir::VarKey key) const {
  auto it = reads_.find(code(key));
  return it == reads_.end() ? SlotRead{} : it->second;
}

SystemReads systemReads(const ir::DaeSystem &sys, size_t set) {
  const ir::StateSet &st = sys.stateSets[set];
  SystemLayout layout(sys, set);
  SystemReads reads(st.residuals.size());
  for (size_t r = 0; r < st.residuals.size(); ++r)
    for (ir::VarKey k : variablesOf(st.residuals[r])) {
      SlotRead sr = layout.read(k);
      if (sr.unknown >= 0)
        reads[r].push_back(sr);
    }
  return reads;
}

graph::BipartiteGraph systemGraph(const ir::DaeSystem &sys, size_t set,
                                  const SystemReads &reads, bool solved) {
  const ir::StateSet &st = sys.stateSets[set];
  graph::BipartiteGraph g(static_cast<int>(st.residuals.size()),
                          static_cast<int>(sys.unknowns.size()));
  const std::vector<bool> differential = ir::setDifferential(sys, set);
  for (size_t r = 0; r < reads.size(); ++r) {
    std::vector<int> &row = g.rows[r];
    for (SlotRead sr : reads[r]) {
      if (solved && differential[sr.unknown] && !sr.derivative)
        continue; // a state: known to the solver
      row.push_back(sr.unknown);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  return g;
}

} // namespace ldae::passes
