// Symbolic differentiation over the DAG, memoized so the cost is linear in
// the DAG size: partial derivatives with respect to one variable (at one
// derivative order) and the total time derivative d/dt, which raises every
// variable's derivative order by one and maps `time` to 1. Derivatives of
// piecewise built-ins (abs, sign, min, max, floor, ceil, mod, if) are taken
// branch-wise: they hold wherever the function is differentiable.
#pragma once

#include "ir/ExprContext.h"
#include "ir/NodeMap.h"

namespace ldae::ir {

class Differentiator {
public:
  explicit Differentiator(ExprContext &ctx) : ctx_(ctx) {}

  /// ∂e/∂v where v is Variable(key.var, key.order); other orders are
  /// independent symbols.
  ExprRef partial(ExprRef e, VarKey key);
  /// d/dt e: ∂e/∂t + Σ ∂e/∂x⁽ᵏ⁾ · x⁽ᵏ⁺¹⁾. `pre(v)` and parameters are
  /// constant between events.
  ExprRef timeDerivative(ExprRef e);

private:
  ExprContext &ctx_;
  VarKey cachedKey_{~0u, ~0u};
  NodeMap<ExprRef> partialCache_; // for cachedKey_
  NodeMap<ExprRef> timeCache_;
};

} // namespace ldae::ir
