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
  ExprRef apply(ExprRef e);

private:
  ExprContext &ctx_;
  std::unordered_map<ExprRef, ExprRef> map_;
  NodeMap<ExprRef> memo_;
};

/// Rebuilds `e` with new operands (same kind, function, comparison...).
ExprRef rebuild(ExprContext &ctx, ExprRef e, std::span<const ExprRef> ops);

} // namespace ldae::ir
