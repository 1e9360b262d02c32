// Double-precision evaluation of expressions: the reference semantics the
// JIT and emitted C must reproduce. Domain errors (log of a negative number,
// division by zero, sqrt of a negative number...) are reported as errors
// naming the offending subexpression, never as silent NaN.
#pragma once

#include "ir/Expr.h"
#include "support/Expected.h"

#include <functional>
#include <span>
#include <string>

namespace ldae::ir {

class NameResolver;

/// Where an evaluation finds the values of leaves.
struct EvalEnv {
  double time = 0;
  std::function<double(VarKey)> variable;
  std::function<double(ParamId)> parameter;
  std::function<double(VarId)> pre; // defaults to variable({v, 0})
};

/// Evaluates `e`; on a domain error returns an Error whose message names
/// the subexpression (printed with `names` when given).
Expected<double> evaluate(ExprRef e, const EvalEnv &env,
                          const NameResolver *names = nullptr);

/// The value of a built-in at double arguments, NaN outside its domain
/// (shared by the evaluator, constant folding and tests).
double applyFunc(FuncKind f, double a, double b = 0);
/// The value of `a <c> b`.
bool applyCompare(CompareKind c, double a, double b);

} // namespace ldae::ir
