// Read-only queries over expressions: free variables, incidence, sizes.
#pragma once

#include "ir/Expr.h"

#include <vector>

namespace ldae::ir {

/// The distinct Variable nodes of `e` as keys, sorted.
std::vector<VarKey> freeVariables(ExprRef e);
/// The distinct parameters of `e`, sorted.
std::vector<ParamId> freeParameters(ExprRef e);
/// True if `e` contains Variable(key).
bool dependsOn(ExprRef e, VarKey key);
/// True if `e` contains any Variable node of variable `v` (any order).
bool dependsOnAnyOrder(ExprRef e, VarId v);
/// Highest derivative order of `v` in `e`, or -1 if it does not occur.
int maxOrder(ExprRef e, VarId v);
/// True if `e` contains Time.
bool dependsOnTime(ExprRef e);
/// Number of distinct nodes reachable from `e`.
size_t dagSize(ExprRef e);
/// Distinct nodes reachable from `roots`, operands before users.
std::vector<ExprRef> topologicalOrder(std::span<const ExprRef> roots);

} // namespace ldae::ir
