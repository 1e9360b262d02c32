// Substitution of subexpressions and rebuilding of nodes through the
// simplifying builders.
#include "ir/Substitute.h"

#include "Traverse.h"
#include "ir/Query.h"

#include <cassert>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace ldae::ir {

ExprRef rebuild(ExprContext &ctx, ExprRef e, std::span<const ExprRef> ops) {
  switch (e->kind()) {
  case ExprKind::Constant:
  case ExprKind::Parameter:
  case ExprKind::Variable:
  case ExprKind::Time:
  case ExprKind::Pre:
    return e;
  case ExprKind::Add:
    return ctx.add(ops);
  case ExprKind::Mul:
    return ctx.mul(ops);
  case ExprKind::Pow:
    return ctx.pow(ops[0], ops[1]);
  case ExprKind::Call:
    return ctx.call(e->func(), ops);
  case ExprKind::External:
    return ctx.external(e->externalId(), e->externalOutput(), ops,
                        static_cast<uint64_t>(e->constant()));
  case ExprKind::If:
    return ctx.ifThenElse(ops[0], ops[1], ops[2]);
  case ExprKind::Compare:
    return ctx.compare(e->compare(), ops[0], ops[1], e->noEvent());
  case ExprKind::And:
    return ctx.logicalAnd(ops);
  case ExprKind::Or:
    return ctx.logicalOr(ops);
  case ExprKind::Not:
    return ctx.logicalNot(ops[0]);
  }
  assert(false && "unknown expression kind");
  return e;
}

ExprRef withNoEvent(ExprContext &ctx, ExprRef e) {
  // Operands before users: a relation inside a relation is marked first.
  Substitution marked(ctx);
  ExprRef roots[] = {e};
  for (ExprRef n : topologicalOrder(roots))
    if (n->kind() == ExprKind::Compare && !n->noEvent())
      marked.set(n, ctx.compare(n->compare(), marked.apply(n->operand(0)),
                                marked.apply(n->operand(1)), true));
  return marked.apply(e);
}

void Substitution::set(ExprRef from, ExprRef to) {
  map_[from] = to;
  memo_.clear(); // earlier results may contain `from`
}

ExprRef Substitution::apply(ExprRef e) {
  if (ExprRef *known = memo_.find(e))
    return *known;
  std::vector<ExprRef> ops;
  ExprRef roots[] = {e};
  postOrder(
      roots,
      [&](ExprRef n) {
        if (memo_.contains(n))
          return true;
        // A replaced node is not entered: its operands do not matter.
        if (auto it = map_.find(n); it != map_.end()) {
          memo_.insert(n, it->second);
          return true;
        }
        return false;
      },
      [&](ExprRef n) {
        ExprRef result = n;
        if (n->numOperands() != 0) {
          ops.clear();
          bool changed = false;
          for (ExprRef op : n->operands()) {
            ops.push_back(*memo_.find(op));
            changed = changed || ops.back() != op;
          }
          if (changed)
            result = rebuild(ctx_, n, ops);
        }
        memo_.insert(n, result);
      });
  return *memo_.find(e);
}

/// `r = 0` solved for variable v when r is linear in it with a constant
/// coefficient (`on - (s < 0)`, `2 * n - m`); null otherwise.
ExprRef solveLinear(ExprContext &ctx, ExprRef r, VarId v) {
  // An if-equation's residual, `if c then y - a else y - b` (MSL's
  // Digital.Sources.Pulse): solved branch by branch when c does not read v.
  if (r->kind() == ExprKind::If) {
    bool condReadsV = false;
    for (VarKey k : freeVariables(r->operand(0)))
      condReadsV = condReadsV || k.var == v;
    if (!condReadsV) {
      ExprRef then = solveLinear(ctx, r->operand(1), v);
      ExprRef otherwise = then ? solveLinear(ctx, r->operand(2), v) : nullptr;
      if (then && otherwise)
        return ctx.ifThenElse(r->operand(0), then, otherwise);
    }
  }
  auto at = [&](double x) {
    Substitution s(ctx);
    s.set(ctx.var(v), ctx.constant(x));
    return s.apply(r);
  };
  ExprRef r0 = at(0), a = ctx.sub(at(1), r0);
  if (a->isConstant() && !a->isConstant(0) &&
      ctx.sub(at(2), r0) == ctx.mul(ctx.constant(2), a))
    return ctx.div(ctx.neg(r0), a);
  // The sums keep `0 * t` for a term t that may be undefined (a division
  // by a parameter: `count - floor(p0 / p1)`, MSL's Trapezoid, or
  // `sa > tau0 / unitTorque` in MSL's friction), so the difference above
  // is not a constant. Linear all the same when no function, if or
  // relation in r reads v (the others are constant in v: their
  // branch-wise derivatives hide no nonlinearity in it) and v's
  // coefficient is constant.
  std::unordered_set<const Expr *> readsV;
  for (ExprRef n : topologicalOrder(std::span(&r, 1))) {
    ExprKind k = n->kind();
    bool reads = k == ExprKind::Variable && n->var() == v && n->order() == 0;
    for (ExprRef o : n->operands())
      reads = reads || readsV.count(o);
    if (!reads)
      continue;
    readsV.insert(n);
    bool arithmetic = k == ExprKind::Add || k == ExprKind::Mul ||
                      k == ExprKind::Variable;
    if (!arithmetic)
      return nullptr;
  }
  // v's coefficient from the sums and products that read it only: a term
  // that does not read v contributes exactly nothing (its derivative would
  // be `0 * t`, kept for a t that may be undefined: MSL's normal quantile
  // beside a noise block's pre(r)).
  std::unordered_map<const Expr *, double> coefficient;
  for (ExprRef n : topologicalOrder(std::span(&r, 1))) {
    if (!readsV.count(n))
      continue;
    double c = 0;
    switch (n->kind()) {
    case ExprKind::Variable:
      c = 1;
      break;
    case ExprKind::Add:
      for (ExprRef o : n->operands())
        if (readsV.count(o))
          c += coefficient[o];
      break;
    default: { // Mul: linear only with one factor reading v, the rest known
      int reading = 0;
      c = 1;
      for (ExprRef o : n->operands()) {
        if (readsV.count(o)) {
          ++reading;
          c *= coefficient[o];
        } else if (o->isConstant()) {
          c *= o->constant();
        } else {
          return nullptr;
        }
      }
      if (reading != 1)
        return nullptr;
    }
    }
    coefficient[n] = c;
  }
  double coef = coefficient[r];
  if (coef == 0 || !std::isfinite(coef))
    return nullptr;
  return ctx.div(ctx.neg(r0), ctx.constant(coef));
}

} // namespace ldae::ir
