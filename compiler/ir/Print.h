// Printing expressions: as lsd source (re-parsable, minimal parentheses,
// `a - b` and `a / b` restored from canonical forms) and as a compact debug
// form showing the DAG's node ids.
#pragma once

#include "ir/ExprContext.h"

#include <string>
#include <utility>

namespace ldae::ir {

/// Supplies the user's names of variables and parameters.
class NameResolver {
public:
  virtual ~NameResolver() = default;
  virtual std::string variableName(VarId v) const = 0;
  virtual std::string parameterName(ParamId p) const = 0;
  /// The (actual, simplified) of a homotopy() call the frontend lowered to
  /// the If node `e`, so the call prints as written; null otherwise.
  virtual const std::pair<ExprRef, ExprRef> *homotopyOf(ExprRef) const {
    return nullptr;
  }
  /// Names printed as they are, not quoted: built-in calls kept as
  /// variables (`initial()`, `sample(0, 1)`) and the discrete slots of the
  /// events pass (`pre(heat)`).
  virtual bool verbatimVariable(VarId) const { return false; }
  virtual bool verbatimParameter(ParamId) const { return false; }
};

/// lsd syntax: `der(x)`, `der(der(x))`, `pre(v)`, `time`, names from `names`
/// (or `v3`, `p2` when null; quoted when not identifiers). Constants print
/// with the shortest digits that read back exactly.
std::string printLsd(ExprRef e, const NameResolver *names = nullptr);
/// printLsd cut to about `maxChars` characters (ending in `...`): for
/// messages about subexpressions of large, heavily shared DAGs.
std::string printLsdBrief(ExprRef e, const NameResolver *names = nullptr,
                          size_t maxChars = 160);
/// `name` as an lsd identifier: unchanged when it is one, else quoted
/// Modelica-style (`'r1.v'`, `'m[2].s'`).
std::string printIdentifier(const std::string &name);
/// The equation `residual = 0` as `lhs = rhs`: terms with a negative sign
/// move to the right (`der(x) = v` for der(x) - v), the constant too; when
/// nothing is left on a side it prints `0`. lhs - rhs rebuilds `residual`.
std::string printEquation(ExprContext &ctx, ExprRef residual,
                          const NameResolver *names = nullptr);
/// `text` as an lsd string literal: `"V"`, with `"` and `\` escaped.
std::string printString(const std::string &text);
/// Compact debug form, e.g. `(+ #3 (* -1 #5))` with node ids.
std::string printDebug(ExprRef e, const NameResolver *names = nullptr);
/// A double as lsd prints it: shortest text that reads back exactly.
std::string printNumber(double v);

} // namespace ldae::ir
