// Iterative DAG traversal shared by the IR algorithms. No recursion: a DAG
// built from a long chain can be a million nodes deep.
#pragma once

#include "ir/Expr.h"

#include <span>
#include <utility>
#include <vector>

namespace ldae::ir {

/// A set of nodes keyed by their dense creation ids.
class NodeSet {
public:
  /// Inserts `e`; false if it was already there.
  bool insert(ExprRef e) {
    uint32_t id = e->id();
    if (id >= bits_.size())
      bits_.resize(std::max<size_t>(id + 1, bits_.size() * 2), false);
    if (bits_[id])
      return false;
    bits_[id] = true;
    return true;
  }
  bool contains(ExprRef e) const {
    return e->id() < bits_.size() && bits_[e->id()];
  }

private:
  std::vector<bool> bits_;
};

/// Calls `visit(e)` once for every node reachable from `roots`, operands
/// before users, without entering nodes for which `prune(e)` is true.
template <typename Prune, typename Visit>
void postOrder(std::span<const ExprRef> roots, Prune &&prune, Visit &&visit) {
  NodeSet seen;
  std::vector<std::pair<ExprRef, unsigned>> stack;
  for (ExprRef root : roots) {
    if (prune(root) || !seen.insert(root))
      continue;
    stack.push_back({root, 0});
    while (!stack.empty()) {
      ExprRef e = stack.back().first;
      unsigned i = stack.back().second;
      if (i < e->numOperands()) {
        ++stack.back().second;
        ExprRef op = e->operand(i);
        if (!prune(op) && seen.insert(op))
          stack.push_back({op, 0});
      } else {
        stack.pop_back();
        visit(e);
      }
    }
  }
}

template <typename Visit>
void postOrder(std::span<const ExprRef> roots, Visit &&visit) {
  postOrder(roots, [](ExprRef) { return false; }, visit);
}

} // namespace ldae::ir
