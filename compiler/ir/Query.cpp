// Read-only queries over expressions (free variables, incidence, sizes),
// each one iterative pass over the DAG.
#include "ir/Query.h"
#include "Traverse.h"

#include <algorithm>

namespace ldae::ir {

namespace {

/// True if some node reachable from `e` satisfies `pred`. Stops early.
template <typename Pred> bool anyNode(ExprRef e, Pred &&pred) {
  bool found = false;
  ExprRef roots[] = {e};
  postOrder(
      roots, [&](ExprRef) { return found; },
      [&](ExprRef n) { found = found || pred(n); });
  return found;
}

} // namespace

namespace {

/// The sorted values `get(n)` of the nodes of `kind` below `e`.
template <typename T, typename Get>
std::vector<T> collectSorted(ExprRef e, ExprKind kind, Get &&get) {
  std::vector<T> out;
  ExprRef roots[] = {e};
  postOrder(roots, [&](ExprRef n) {
    if (n->kind() == kind)
      out.push_back(get(n));
  });
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace

std::vector<VarKey> freeVariables(ExprRef e) {
  return collectSorted<VarKey>(e, ExprKind::Variable,
                               [](ExprRef n) { return n->varKey(); });
}

std::vector<ParamId> freeParameters(ExprRef e) {
  return collectSorted<ParamId>(e, ExprKind::Parameter,
                                [](ExprRef n) { return n->param(); });
}

bool dependsOn(ExprRef e, VarKey key) {
  return anyNode(e, [&](ExprRef n) {
    return n->kind() == ExprKind::Variable && n->varKey() == key;
  });
}

bool dependsOnAnyOrder(ExprRef e, VarId v) {
  return anyNode(e, [&](ExprRef n) {
    return n->kind() == ExprKind::Variable && n->var() == v;
  });
}

int maxOrder(ExprRef e, VarId v) {
  int order = -1;
  ExprRef roots[] = {e};
  postOrder(roots, [&](ExprRef n) {
    if (n->kind() == ExprKind::Variable && n->var() == v)
      order = std::max(order, static_cast<int>(n->order()));
  });
  return order;
}

bool dependsOnTime(ExprRef e) {
  return anyNode(e, [](ExprRef n) { return n->kind() == ExprKind::Time; });
}

size_t dagSize(ExprRef e) {
  size_t n = 0;
  ExprRef roots[] = {e};
  postOrder(roots, [&](ExprRef) { ++n; });
  return n;
}

std::vector<ExprRef> topologicalOrder(std::span<const ExprRef> roots) {
  std::vector<ExprRef> order;
  postOrder(roots, [&](ExprRef n) { order.push_back(n); });
  return order;
}

} // namespace ldae::ir
