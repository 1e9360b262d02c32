// Iterative DAG traversal shared by the IR algorithms. No recursion: a DAG
// built from a long chain can be a million nodes deep.
#pragma once

#include "ir/NodeMap.h"

#include <span>
#include <utility>
#include <vector>

namespace ldae::ir {

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
  postOrder(
      roots, [](ExprRef) { return false; }, visit);
}

} // namespace ldae::ir
