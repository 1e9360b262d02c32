// Replaces subexpressions (usually leaves: variables, parameters) by other
// expressions, rebuilding through the simplifying builders. Memoized per
// Substitution object, so a shared subexpression is rewritten once.
#pragma once

#include "ir/ExprContext.h"
#include "ir/NodeMap.h"

#include <unordered_map>

namespace ldae::ir {

class Substitution {
public:
  explicit Substitution(ExprContext &ctx) : ctx_(ctx) {}
  /// Every occurrence of `from` is replaced by `to`.
  void set(ExprRef from, ExprRef to);
  /// As set(), keeping the memo: for callers that know no expression
  /// rewritten so far contains `from` (values defined in solve order, each
  /// reading only earlier ones), so a long chain costs linear time.
  void extend(ExprRef from, ExprRef to) { map_[from] = to; }
  ExprRef apply(ExprRef e);

private:
  ExprContext &ctx_;
  std::unordered_map<ExprRef, ExprRef> map_;
  NodeMap<ExprRef> memo_;
};

/// `e` with every relation marked noEvent (Expr::noEvent): `noEvent(e)`.
ExprRef withNoEvent(ExprContext &ctx, ExprRef e);

/// `r = 0` solved for variable v when r is linear in it with a constant
/// coefficient (`on - (s < 0)`, `2 * n - m`); null otherwise.
ExprRef solveLinear(ExprContext &ctx, ExprRef r, VarId v);

/// Rebuilds `e` with new operands (same kind, function, comparison...).
ExprRef rebuild(ExprContext &ctx, ExprRef e, std::span<const ExprRef> ops);

} // namespace ldae::ir
