// Symbolic differentiation: the chain rule applied once per DAG node in
// topological order, so shared subexpressions are differentiated once and
// the cost is linear in the DAG size. The leaf rule is the only difference
// between a partial derivative and the total time derivative.
#include "ir/Differentiate.h"
#include "Traverse.h"

#include <cassert>
#include <cmath>

namespace ldae::ir {

namespace {

/// Whether `e` has an if-expression in it (a piecewise derivative).
bool readsIf(ExprRef e) {
  bool found = false;
  postOrder(std::span<const ExprRef>(&e, 1),
            [&](ExprRef) { return found; },
            [&](ExprRef x) { found = found || x->kind() == ExprKind::If; });
  return found;
}

/// d(e) given the derivatives `d(op)` of e's operands (already computed).
/// Zero derivatives are tested structurally before multiplying, so a
/// product never carries `0 * f'(x)` for a partial f (which the simplifier
/// would have to keep when f' has a singularity).
template <typename D> ExprRef chainRule(ExprContext &ctx, ExprRef e, D &&d) {
  auto isZero = [](ExprRef x) { return x->isConstant(0); };
  auto scale = [&](ExprRef factor, ExprRef da) {
    return isZero(da) ? ctx.zero() : ctx.mul(factor, da);
  };
  switch (e->kind()) {
  case ExprKind::Add: {
    std::vector<ExprRef> terms;
    for (ExprRef op : e->operands())
      if (ExprRef dop = d(op); !isZero(dop))
        terms.push_back(dop);
    return ctx.add(terms);
  }
  case ExprKind::Mul: {
    std::vector<ExprRef> terms;
    unsigned n = e->numOperands();
    for (unsigned i = 0; i < n; ++i) {
      ExprRef dop = d(e->operand(i));
      if (isZero(dop))
        continue;
      std::vector<ExprRef> factors;
      factors.reserve(n);
      for (unsigned j = 0; j < n; ++j)
        factors.push_back(j == i ? dop : e->operand(j));
      terms.push_back(ctx.mul(factors));
    }
    return ctx.add(terms);
  }
  case ExprKind::Pow: {
    ExprRef a = e->operand(0), b = e->operand(1);
    ExprRef da = d(a), db = d(b);
    ExprRef result = ctx.zero();
    if (!isZero(da) && !isZero(b)) { // a^0 is constant where defined
      // b * a^(b-1) * a'
      ExprRef factors[] = {b, ctx.pow(a, ctx.sub(b, ctx.one())), da};
      result = ctx.mul(factors);
    }
    if (!isZero(db)) {
      // a^b * log(a) * b'
      ExprRef factors[] = {e, ctx.call(FuncKind::Log, a), db};
      result = ctx.add(result, ctx.mul(factors));
    }
    return result;
  }
  case ExprKind::External: {
    // C code has no symbolic derivative: each partial is a central
    // difference with a step relative to the argument (eps^(1/3) scale),
    // itself an expression, so it can be differentiated again.
    std::vector<ExprRef> terms;
    std::vector<ExprRef> args(e->operands().begin(), e->operands().end());
    auto serial = static_cast<uint64_t>(e->constant());
    for (unsigned i = 0; i < e->numOperands(); ++i) {
      ExprRef da = d(e->operand(i));
      if (isZero(da))
        continue;
      ExprRef x = e->operand(i);
      ExprRef h = ctx.mul(ctx.constant(1e-6),
                          ctx.add(ctx.one(), ctx.call(FuncKind::Abs, x)));
      std::vector<ExprRef> up = args, down = args;
      up[i] = ctx.add(x, h);
      down[i] = ctx.sub(x, h);
      ExprRef diff =
          ctx.sub(ctx.external(e->externalId(), e->externalOutput(), up, serial),
                  ctx.external(e->externalId(), e->externalOutput(), down,
                               serial));
      ExprRef factors[] = {diff, ctx.pow(ctx.mul(ctx.constant(2), h),
                                         ctx.constant(-1)),
                           da};
      terms.push_back(ctx.mul(factors));
    }
    return ctx.add(terms);
  }
  case ExprKind::Call: {
    ExprRef a = e->operand(0);
    ExprRef da = d(a);
    auto minus1 = ctx.constant(-1);
    switch (e->func()) {
    case FuncKind::Sin:
      return scale(ctx.call(FuncKind::Cos, a), da);
    case FuncKind::Cos:
      return scale(ctx.neg(ctx.call(FuncKind::Sin, a)), da);
    case FuncKind::Tan: // 1 / cos(a)^2
      return scale(ctx.pow(ctx.call(FuncKind::Cos, a), ctx.constant(-2)), da);
    case FuncKind::Asin: // (1 - a^2)^-1/2
    case FuncKind::Acos: {
      if (isZero(da))
        return ctx.zero();
      ExprRef r = ctx.pow(ctx.sub(ctx.one(), ctx.pow(a, ctx.constant(2))),
                          ctx.constant(-0.5));
      if (e->func() == FuncKind::Acos)
        r = ctx.neg(r);
      return ctx.mul(r, da);
    }
    case FuncKind::Atan: // 1 / (1 + a^2)
      if (isZero(da))
        return ctx.zero();
      return ctx.mul(
          ctx.pow(ctx.add(ctx.one(), ctx.pow(a, ctx.constant(2))), minus1), da);
    case FuncKind::Atan2: { // atan2(y, x)' = (x y' - y x') / (x^2 + y^2)
      ExprRef y = a, x = e->operand(1), dy = da, dx = d(x);
      if (isZero(dy) && isZero(dx))
        return ctx.zero();
      ExprRef num = ctx.sub(scale(x, dy), scale(y, dx));
      ExprRef den =
          ctx.add(ctx.pow(x, ctx.constant(2)), ctx.pow(y, ctx.constant(2)));
      return ctx.div(num, den);
    }
    case FuncKind::Sinh:
      return scale(ctx.call(FuncKind::Cosh, a), da);
    case FuncKind::Cosh:
      return scale(ctx.call(FuncKind::Sinh, a), da);
    case FuncKind::Tanh: // 1 - tanh(a)^2
      if (isZero(da))
        return ctx.zero();
      return ctx.mul(ctx.sub(ctx.one(), ctx.pow(e, ctx.constant(2))), da);
    case FuncKind::Exp:
      return scale(e, da);
    case FuncKind::Log:
      return isZero(da) ? ctx.zero() : ctx.div(da, a);
    case FuncKind::Log10:
      return isZero(da) ? ctx.zero()
                        : ctx.div(da, ctx.mul(a, ctx.constant(std::log(10.0))));
    case FuncKind::Sqrt: { // 1 / (2 sqrt(a))
      if (isZero(da))
        return ctx.zero();
      ExprRef chain = ctx.div(da, ctx.mul(ctx.constant(2), e));
      // A piecewise argument clamped at 0 (sqrt(max(0, 2 g level)) of an
      // empty tank, MSL's ControlledTanks) has da = 0 where a = 0, and
      // 0/0 there made every Jacobian a domain error (IDA_CONV_FAIL at
      // each retry): 0 where a does not move. Smooth arguments keep the
      // plain rule (the SGA differentiates it again).
      return readsIf(da) ? ctx.ifThenElse(ctx.compare(CompareKind::Eq, da,
                                                      ctx.zero(),
                                                      /*noEvent=*/true),
                                          ctx.zero(), chain)
                         : chain;
    }
    case FuncKind::Abs:
      return scale(ctx.call(FuncKind::Sign, a), da);
    case FuncKind::Sign:
    case FuncKind::Floor:
    case FuncKind::Ceil:
      return ctx.zero();
    case FuncKind::Min:
    case FuncKind::Max: {
      ExprRef b = e->operand(1), db = d(b);
      if (da == db)
        return da;
      CompareKind c =
          e->func() == FuncKind::Min ? CompareKind::Lt : CompareKind::Gt;
      return ctx.ifThenElse(ctx.compare(c, a, b), da, db);
    }
    case FuncKind::Mod: { // a - floor(a/b)*b
      ExprRef b = e->operand(1), db = d(b);
      if (isZero(db))
        return da;
      return ctx.sub(da, ctx.mul(ctx.call(FuncKind::Floor, ctx.div(a, b)), db));
    }
    }
    assert(false && "unknown function");
    return ctx.zero();
  }
  case ExprKind::If:
    return ctx.ifThenElse(e->operand(0), d(e->operand(1)), d(e->operand(2)));
  case ExprKind::Compare:
  case ExprKind::And:
  case ExprKind::Or:
  case ExprKind::Not:
    return ctx.zero(); // piecewise constant
  default:
    assert(false && "leaves are handled by the caller");
    return ctx.zero();
  }
}

/// Differentiates every node below `e` missing from `cache`, operands first.
template <typename Leaf>
ExprRef differentiate(ExprContext &ctx, ExprRef e, NodeMap<ExprRef> &cache,
                      Leaf &&leaf) {
  if (ExprRef *known = cache.find(e))
    return *known;
  auto d = [&](ExprRef op) {
    ExprRef *dop = cache.find(op);
    assert(dop && "operands are differentiated first");
    return *dop;
  };
  ExprRef roots[] = {e};
  postOrder(
      roots, [&](ExprRef n) { return cache.contains(n); },
      [&](ExprRef n) {
        cache.insert(n, n->numOperands() == 0 ? leaf(n) : chainRule(ctx, n, d));
      });
  return *cache.find(e);
}

} // namespace

ExprRef Differentiator::partial(ExprRef e, VarKey key) {
  if (key != cachedKey_) {
    partialCache_.clear();
    cachedKey_ = key;
  }
  return differentiate(ctx_, e, partialCache_, [&](ExprRef leaf) {
    return leaf->kind() == ExprKind::Variable && leaf->varKey() == key
               ? ctx_.one()
               : ctx_.zero();
  });
}

ExprRef Differentiator::timeDerivative(ExprRef e) {
  return differentiate(ctx_, e, timeCache_, [&](ExprRef leaf) {
    switch (leaf->kind()) {
    case ExprKind::Variable:
      return ctx_.var(leaf->var(), leaf->order() + 1);
    case ExprKind::Time:
      return ctx_.one();
    default: // constants, parameters, pre(v): constant between events
      return ctx_.zero();
    }
  });
}

} // namespace ldae::ir
