// Printing expressions: as lsd source (re-parsable, minimal parentheses,
// `a - b` and `a / b` restored from canonical forms) and as a compact debug
// form showing the DAG's node ids.
#pragma once

#include "ir/Expr.h"

#include <string>

namespace ldae::ir {

/// Supplies the user's names of variables and parameters.
class NameResolver {
public:
  virtual ~NameResolver() = default;
  virtual std::string variableName(VarId v) const = 0;
  virtual std::string parameterName(ParamId p) const = 0;
};

/// lsd syntax: `der(x)`, `der(x, 2)`, `pre(v)`, `time`, names from `names`
/// (or `v3`, `p2` when null). Constants print with 17 significant digits.
std::string printLsd(ExprRef e, const NameResolver *names = nullptr);
/// Compact debug form, e.g. `(+ #3 (* -1 #5))` with node ids.
std::string printDebug(ExprRef e, const NameResolver *names = nullptr);
/// A double as lsd prints it: shortest text that reads back exactly.
std::string printNumber(double v);

} // namespace ldae::ir
