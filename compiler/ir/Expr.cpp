// Names and arities of built-in functions and comparisons, and the Expr
// predicates that need no context.
#include "ir/Expr.h"

#include <cassert>

namespace ldae::ir {

unsigned funcArity(FuncKind f) {
  switch (f) {
  case FuncKind::Atan2:
  case FuncKind::Min:
  case FuncKind::Max:
  case FuncKind::Mod:
    return 2;
  default:
    return 1;
  }
}

const char *funcName(FuncKind f) {
  switch (f) {
  case FuncKind::Sin:
    return "sin";
  case FuncKind::Cos:
    return "cos";
  case FuncKind::Tan:
    return "tan";
  case FuncKind::Asin:
    return "asin";
  case FuncKind::Acos:
    return "acos";
  case FuncKind::Atan:
    return "atan";
  case FuncKind::Atan2:
    return "atan2";
  case FuncKind::Sinh:
    return "sinh";
  case FuncKind::Cosh:
    return "cosh";
  case FuncKind::Tanh:
    return "tanh";
  case FuncKind::Exp:
    return "exp";
  case FuncKind::Log:
    return "log";
  case FuncKind::Log10:
    return "log10";
  case FuncKind::Sqrt:
    return "sqrt";
  case FuncKind::Abs:
    return "abs";
  case FuncKind::Sign:
    return "sign";
  case FuncKind::Min:
    return "min";
  case FuncKind::Max:
    return "max";
  case FuncKind::Floor:
    return "floor";
  case FuncKind::Ceil:
    return "ceil";
  case FuncKind::Mod:
    return "mod";
  }
  assert(false && "unknown function");
  return "?";
}

const char *compareSymbol(CompareKind c) {
  switch (c) {
  case CompareKind::Lt:
    return "<";
  case CompareKind::Le:
    return "<=";
  case CompareKind::Gt:
    return ">";
  case CompareKind::Ge:
    return ">=";
  case CompareKind::Eq:
    return "==";
  case CompareKind::Ne:
    return "<>";
  }
  assert(false && "unknown comparison");
  return "?";
}

bool Expr::isBoolean() const {
  switch (kind_) {
  case ExprKind::Compare:
  case ExprKind::And:
  case ExprKind::Or:
  case ExprKind::Not:
    return true;
  default:
    return false;
  }
}

} // namespace ldae::ir
