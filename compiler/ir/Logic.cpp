// The simplifying builders of ExprContext for built-in calls, conditionals,
// comparisons and logic: constant folding (through applyFunc, the same
// semantics the evaluator uses) and a few identities that hold wherever the
// input is defined (docs/ir.md).
#include "ExprContextImpl.h"
#include "ir/Evaluate.h"

#include <algorithm>
#include <cassert>

namespace ldae::ir {

namespace {

CompareKind negateCompare(CompareKind c) {
  switch (c) {
  case CompareKind::Lt:
    return CompareKind::Ge;
  case CompareKind::Le:
    return CompareKind::Gt;
  case CompareKind::Gt:
    return CompareKind::Le;
  case CompareKind::Ge:
    return CompareKind::Lt;
  case CompareKind::Eq:
    return CompareKind::Ne;
  case CompareKind::Ne:
    return CompareKind::Eq;
  }
  return c;
}

} // namespace

ExprRef ExprContext::call(FuncKind f, std::span<const ExprRef> args) {
  assert(args.size() == funcArity(f) && "wrong number of arguments");
  bool allConstant = std::all_of(args.begin(), args.end(),
                                 [](ExprRef a) { return a->isConstant(); });
  if (allConstant) {
    double r = applyFunc(f, args[0]->constant(),
                         args.size() > 1 ? args[1]->constant() : 0.0);
    if (std::isfinite(r))
      return constant(r);
  }
  switch (f) {
  case FuncKind::Abs:
  case FuncKind::Sign:
  case FuncKind::Floor:
  case FuncKind::Ceil:
    // Idempotent: abs(abs(x)) = abs(x), floor(floor(x)) = floor(x)...
    if (args[0]->kind() == ExprKind::Call && args[0]->func() == f)
      return args[0];
    break;
  case FuncKind::Min:
  case FuncKind::Max:
    if (args[0] == args[1])
      return args[0];
    break;
  default:
    break;
  }
  return intern(ExprKind::Call, static_cast<uint8_t>(f), 0, 0, 0, args);
}

ExprRef ExprContext::call(FuncKind f, ExprRef a) {
  ExprRef ops[] = {a};
  return call(f, ops);
}

ExprRef ExprContext::call(FuncKind f, ExprRef a, ExprRef b) {
  ExprRef ops[] = {a, b};
  return call(f, ops);
}

ExprRef ExprContext::ifThenElse(ExprRef cond, ExprRef then, ExprRef otherwise) {
  if (cond->isConstant())
    return cond->constant() != 0 ? then : otherwise;
  if (then == otherwise && isTotal(cond))
    return then;
  if (cond->kind() == ExprKind::Not)
    return ifThenElse(cond->operand(0), otherwise, then);
  ExprRef ops[] = {cond, then, otherwise};
  return intern(ExprKind::If, 0, 0, 0, 0, ops);
}

ExprRef ExprContext::compare(CompareKind c, ExprRef a, ExprRef b,
                             bool noEvent) {
  if (a->isConstant() && b->isConstant())
    return constant(applyCompare(c, a->constant(), b->constant()) ? 1 : 0);
  if (a == b && isTotal(a))
    return constant(applyCompare(c, 0, 0) ? 1 : 0);
  ExprRef ops[] = {a, b};
  uint8_t sub = static_cast<uint8_t>(c) | (noEvent ? Expr::kNoEventBit : 0);
  return intern(ExprKind::Compare, sub, 0, 0, 0, ops);
}

namespace {

/// Shared body of `and` / `or`: `absorbing` is the constant that decides the
/// result (0 for and, 1 for or); the other truth value is neutral.
struct LogicParts {
  std::vector<ExprRef> ops;
  bool absorbed = false;
};

LogicParts collectLogic(ExprKind kind, std::span<const ExprRef> in,
                        bool absorbingIsTrue) {
  LogicParts parts;
  auto take = [&](ExprRef e) {
    if (!e->isConstant())
      parts.ops.push_back(e);
    else if ((e->constant() != 0) == absorbingIsTrue)
      parts.absorbed = true; // else neutral: dropped
  };
  for (ExprRef e : in) {
    if (e->kind() == kind) {
      for (ExprRef op : e->operands())
        take(op);
    } else {
      take(e);
    }
  }
  std::sort(parts.ops.begin(), parts.ops.end(), ExprIdLess());
  parts.ops.erase(std::unique(parts.ops.begin(), parts.ops.end()),
                  parts.ops.end());
  return parts;
}

} // namespace

ExprRef ExprContext::buildLogic(ExprKind kind, std::span<const ExprRef> in) {
  // and: false absorbs, true is neutral; or: the other way round.
  bool isAnd = kind == ExprKind::And;
  ExprRef absorbing = isAnd ? zero() : one();
  LogicParts parts = collectLogic(kind, in, !isAnd);
  bool allTotal = std::all_of(parts.ops.begin(), parts.ops.end(),
                              [&](ExprRef e) { return isTotal(e); });
  if (parts.absorbed) {
    if (allTotal)
      return absorbing;
    parts.ops.insert(parts.ops.begin(), absorbing);
  }
  if (parts.ops.empty())
    return isAnd ? one() : zero();
  if (parts.ops.size() == 1 && parts.ops[0]->isBoolean())
    return parts.ops[0];
  return intern(kind, 0, 0, 0, 0, parts.ops);
}

ExprRef ExprContext::logicalAnd(std::span<const ExprRef> in) {
  return buildLogic(ExprKind::And, in);
}

ExprRef ExprContext::logicalAnd(ExprRef a, ExprRef b) {
  ExprRef ops[] = {a, b};
  return logicalAnd(ops);
}

ExprRef ExprContext::logicalOr(std::span<const ExprRef> in) {
  return buildLogic(ExprKind::Or, in);
}

ExprRef ExprContext::logicalOr(ExprRef a, ExprRef b) {
  ExprRef ops[] = {a, b};
  return logicalOr(ops);
}

ExprRef ExprContext::logicalNot(ExprRef a) {
  if (a->isConstant())
    return constant(a->constant() == 0 ? 1 : 0);
  if (a->kind() == ExprKind::Not && a->operand(0)->isBoolean())
    return a->operand(0);
  if (a->kind() == ExprKind::Compare)
    return compare(negateCompare(a->compare()), a->operand(0), a->operand(1),
                   a->noEvent());
  ExprRef ops[] = {a};
  return intern(ExprKind::Not, 0, 0, 0, 0, ops);
}

} // namespace ldae::ir
