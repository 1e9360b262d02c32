// Creates, uniques and owns expression nodes. Every builder simplifies at
// construction (constant folding, neutral and absorbing elements, like terms
// and powers collected, canonical operand order) without ever changing the
// value of an expression where it is defined: `x/x` becomes 1 only when x is
// a nonzero constant, `0*x` becomes 0 only when x cannot be inf/NaN by
// construction (see docs/ir.md for the exact rules).
#pragma once

#include "ir/Expr.h"

#include <memory>
#include <vector>

namespace ldae::ir {

class ExprContext {
public:
  ExprContext();
  ~ExprContext();
  ExprContext(const ExprContext &) = delete;
  ExprContext &operator=(const ExprContext &) = delete;

  // Leaves.
  ExprRef constant(double v);
  ExprRef zero() { return constant(0.0); }
  ExprRef one() { return constant(1.0); }
  ExprRef param(ParamId p);
  ExprRef var(VarId v, unsigned order = 0);
  ExprRef var(VarKey k) { return var(k.var, k.order); }
  ExprRef time();
  ExprRef pre(VarId v);

  // Arithmetic. Subtraction, negation and division are canonical forms:
  // a - b = a + (-1)*b, -a = (-1)*a, a / b = a * b^-1.
  ExprRef add(std::span<const ExprRef> terms);
  ExprRef add(ExprRef a, ExprRef b);
  ExprRef sub(ExprRef a, ExprRef b);
  ExprRef neg(ExprRef a);
  ExprRef mul(std::span<const ExprRef> factors);
  ExprRef mul(ExprRef a, ExprRef b);
  ExprRef div(ExprRef a, ExprRef b);
  ExprRef pow(ExprRef base, ExprRef exponent);

  /// A built-in function; `args.size()` must equal funcArity(f).
  ExprRef call(FuncKind f, std::span<const ExprRef> args);
  ExprRef call(FuncKind f, ExprRef a);
  ExprRef call(FuncKind f, ExprRef a, ExprRef b);

  /// Output `output` of external function `id` (ir/External.h) at `args`,
  /// one double per input of its wrapper. `serial` tells apart calls of an
  /// impure function (0 for pure ones, which are shared like any node).
  ExprRef external(uint32_t id, unsigned output, std::span<const ExprRef> args,
                   uint64_t serial = 0);

  // Conditionals and logic. Booleans are expressions valued 0 or 1.
  ExprRef ifThenElse(ExprRef cond, ExprRef then, ExprRef otherwise);
  /// `noEvent`: the relation as written inside noEvent() (Expr::noEvent).
  ExprRef compare(CompareKind c, ExprRef a, ExprRef b, bool noEvent = false);
  ExprRef logicalAnd(std::span<const ExprRef> ops);
  ExprRef logicalAnd(ExprRef a, ExprRef b);
  ExprRef logicalOr(std::span<const ExprRef> ops);
  ExprRef logicalOr(ExprRef a, ExprRef b);
  ExprRef logicalNot(ExprRef a);

  /// Number of distinct nodes created so far.
  size_t size() const;
  /// Bytes held by the nodes, their operands and the uniquing structures
  /// (for benchmarks).
  size_t memoryBytes() const;

  /// True if `e` is finite and free of domain errors for every finite value
  /// of its leaves (ignoring overflow): the condition under which `0*e`,
  /// `e^0` and cancelled terms may be dropped. See docs/ir.md.
  bool isTotal(ExprRef e) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;

  /// Finds or creates the node with these fields; operands are copied into
  /// the arena. The only place nodes are made.
  ExprRef intern(ExprKind kind, uint8_t sub, uint32_t index, uint16_t order,
                 double value, std::span<const ExprRef> ops);
  /// The body of logicalAnd (kind And) and logicalOr (kind Or).
  ExprRef buildLogic(ExprKind kind, std::span<const ExprRef> ops);
};

} // namespace ldae::ir
