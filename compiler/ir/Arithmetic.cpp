// The simplifying arithmetic builders of ExprContext: sums, products and
// powers. Each result is in canonical form (flattened, like terms and like
// powers collected, constants folded, operands ordered by creation id with
// the constant first) and equals the input wherever the input is defined;
// docs/ir.md lists the rules and why each one is safe.
#include "ExprContextImpl.h"

#include <algorithm>
#include <cassert>

namespace ldae::ir {

namespace {

/// The id a term of a sum sorts by: that of its first symbolic factor, so
/// `2*x` sorts with `x` (terms read in the order their variables were made).
uint32_t termKey(ExprRef t) {
  if (t->kind() == ExprKind::Mul && t->operand(0)->isConstant())
    return t->operand(1)->id();
  return t->id();
}

/// Orders the operands of a sum or product: the constant first, then by
/// key (termKey for sums, the id for products), then by id.
void sortCanonical(std::vector<ExprRef> &ops, bool sum) {
  std::sort(ops.begin(), ops.end(), [sum](ExprRef a, ExprRef b) {
    if (a->isConstant() != b->isConstant())
      return a->isConstant();
    uint32_t ka = sum ? termKey(a) : a->id(), kb = sum ? termKey(b) : b->id();
    return ka != kb ? ka < kb : a->id() < b->id();
  });
}

/// Adds up constants in a fixed order (by value), so a permutation of the
/// operands folds to the same bits.
double foldSum(std::vector<double> &values) {
  std::sort(values.begin(), values.end());
  double s = 0;
  for (double v : values)
    s += v;
  return s;
}

double foldProduct(std::vector<double> &values) {
  std::sort(values.begin(), values.end());
  double p = 1;
  for (double v : values)
    p *= v;
  return p;
}

/// `ops` with every small node of `kind` replaced by its operands.
std::vector<ExprRef> flatten(ExprKind kind, std::span<const ExprRef> ops) {
  std::vector<ExprRef> flat;
  flat.reserve(ops.size() + 4);
  for (ExprRef e : ops) {
    if (e->kind() == kind && e->numOperands() <= kFlattenLimit)
      flat.insert(flat.end(), e->operands().begin(), e->operands().end());
    else
      flat.push_back(e);
  }
  return flat;
}

} // namespace

ExprRef ExprContext::add(std::span<const ExprRef> terms) {
  std::vector<ExprRef> flat = flatten(ExprKind::Add, terms);

  // Split every term into coefficient * rest and collect like terms.
  std::vector<double> constants;
  // The rest of a term is its factors after the coefficient; it is made a
  // node only when like terms merge (a lookup per term would dominate).
  struct Term {
    std::span<const ExprRef> rest;
    double coef;
    ExprRef term;
  };
  auto restLess = [](std::span<const ExprRef> a, std::span<const ExprRef> b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(),
                                        ExprIdLess());
  };
  auto restEqual = [](std::span<const ExprRef> a, std::span<const ExprRef> b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  };
  std::vector<Term> items;
  items.reserve(flat.size());
  for (const ExprRef &t : flat) {
    if (t->isConstant())
      constants.push_back(t->constant());
    else if (t->kind() == ExprKind::Mul && t->operand(0)->isConstant())
      items.push_back({t->operands().subspan(1), t->operand(0)->constant(), t});
    else if (t->kind() == ExprKind::Mul)
      items.push_back({t->operands(), 1.0, t});
    else
      items.push_back({std::span<const ExprRef>(&t, 1), 1.0, t});
  }
  std::sort(items.begin(), items.end(), [&](const Term &a, const Term &b) {
    if (restLess(a.rest, b.rest))
      return true;
    return !restLess(b.rest, a.rest) && a.coef < b.coef;
  });

  std::vector<ExprRef> out;
  out.reserve(items.size() + 1);
  for (size_t i = 0; i < items.size();) {
    size_t j = i;
    double coef = 0;
    for (; j < items.size() && restEqual(items[j].rest, items[i].rest); ++j)
      coef += items[j].coef;
    if (j - i == 1) {
      out.push_back(items[i].term); // alone: already canonical
      i = j;
      continue;
    }
    ExprRef rest = items[i].rest.size() == 1
                       ? items[i].rest[0]
                       : intern(ExprKind::Mul, 0, 0, 0, 0, items[i].rest);
    if (!std::isfinite(coef)) {
      // The coefficients overflowed: keep the terms as they were.
      for (size_t k = i; k < j; ++k)
        out.push_back(mul(constant(items[k].coef), rest));
    } else {
      // A term cancels only if it is total (mul keeps `0 * t` otherwise).
      ExprRef term = mul(constant(coef), rest);
      if (!term->isConstant(0))
        out.push_back(term);
    }
    i = j;
  }

  if (!constants.empty()) {
    double c = foldSum(constants);
    if (!std::isfinite(c)) {
      for (double v : constants)
        out.push_back(constant(v));
    } else if (c != 0) {
      out.push_back(constant(c));
    }
  }
  if (out.empty())
    return zero();
  if (out.size() == 1)
    return out[0];
  sortCanonical(out, true);
  return intern(ExprKind::Add, 0, 0, 0, 0, out);
}

ExprRef ExprContext::add(ExprRef a, ExprRef b) {
  ExprRef ops[] = {a, b};
  return add(ops);
}

ExprRef ExprContext::sub(ExprRef a, ExprRef b) { return add(a, neg(b)); }

ExprRef ExprContext::neg(ExprRef a) { return mul(constant(-1.0), a); }

ExprRef ExprContext::mul(std::span<const ExprRef> factors) {
  std::vector<ExprRef> flat = flatten(ExprKind::Mul, factors);

  // Split every factor into base ^ integer exponent; anything else is its
  // own base with exponent 1.
  std::vector<double> constants;
  struct Factor {
    ExprRef base;
    double exponent;
    ExprRef factor;
  };
  std::vector<Factor> items;
  items.reserve(flat.size());
  for (ExprRef f : flat) {
    if (f->isConstant())
      constants.push_back(f->constant());
    else if (f->kind() == ExprKind::Pow && f->operand(1)->isConstant() &&
             isIntegral(f->operand(1)->constant()))
      items.push_back({f->operand(0), f->operand(1)->constant(), f});
    else
      items.push_back({f, 1.0, f});
  }
  std::sort(items.begin(), items.end(), [](const Factor &a, const Factor &b) {
    return a.base->id() != b.base->id() ? a.base->id() < b.base->id()
                                        : a.exponent < b.exponent;
  });

  // Like bases: exponents of one sign are added (x*x = x^2, x^-1*x^-2 =
  // x^-3); a positive and a negative power are never merged, since that
  // would remove a division by zero (x/x stays x/x).
  std::vector<ExprRef> out;
  out.reserve(items.size() + 1);
  auto emit = [&](ExprRef base, double exponent) {
    ExprRef f = pow(base, constant(exponent));
    if (f->isConstant())
      constants.push_back(f->constant());
    else
      out.push_back(f);
  };
  for (size_t i = 0; i < items.size();) {
    double positive = 0, negative = 0;
    size_t j = i;
    for (; j < items.size() && items[j].base == items[i].base; ++j)
      (items[j].exponent > 0 ? positive : negative) += items[j].exponent;
    if (j - i == 1) {
      out.push_back(items[i].factor); // alone: already canonical
      i = j;
      continue;
    }
    if (positive != 0)
      emit(items[i].base, positive);
    if (negative != 0)
      emit(items[i].base, negative);
    i = j;
  }

  double coef = 1;
  if (!constants.empty()) {
    coef = foldProduct(constants);
    if (!std::isfinite(coef)) {
      for (double v : constants)
        out.push_back(constant(v));
      coef = 1;
    }
  }
  if (coef == 0) {
    bool allTotal = std::all_of(out.begin(), out.end(),
                                [&](ExprRef f) { return isTotal(f); });
    if (allTotal)
      return zero();
  }
  if (out.empty())
    return constant(coef);
  if (out.size() == 1) {
    if (coef == 1)
      return out[0];
    // A number times a small sum is distributed: -(a + b) = -a - b, so a
    // sum and its negation cancel term by term.
    ExprRef s = out[0];
    if (s->kind() == ExprKind::Add && s->numOperands() <= kFlattenLimit &&
        coef != 0) {
      std::vector<ExprRef> terms;
      terms.reserve(s->numOperands());
      ExprRef c = constant(coef);
      for (ExprRef t : s->operands())
        terms.push_back(mul(c, t));
      return add(terms);
    }
  }
  if (coef != 1)
    out.push_back(constant(coef));
  sortCanonical(out, false);
  return intern(ExprKind::Mul, 0, 0, 0, 0, out);
}

ExprRef ExprContext::mul(ExprRef a, ExprRef b) {
  ExprRef ops[] = {a, b};
  return mul(ops);
}

ExprRef ExprContext::div(ExprRef a, ExprRef b) {
  return mul(a, pow(b, constant(-1.0)));
}

ExprRef ExprContext::pow(ExprRef base, ExprRef exponent) {
  if (base->isConstant() && exponent->isConstant()) {
    double b = base->constant(), e = exponent->constant();
    bool domainError = (b == 0 && e < 0) || (b < 0 && !isIntegral(e));
    if (!domainError) {
      double r = std::pow(b, e);
      if (std::isfinite(r))
        return constant(r);
    }
  }
  if (exponent->isConstant()) {
    double e = exponent->constant();
    if (e == 1)
      return base;
    if (e == 0 && isTotal(base))
      return one();
    if (base->isConstant(0) && e > 0)
      return zero();
    // (x^a)^b = x^(a*b) for integer b when both sides have the same domain:
    // x = 0 is excluded on both sides (a > 0 or b > 0), and x < 0 on both
    // sides when a is not an integer (then a*b must not be one either).
    if (base->kind() == ExprKind::Pow && base->operand(1)->isConstant() &&
        isIntegral(e)) {
      double a = base->operand(1)->constant();
      double ab = a * e;
      if ((a > 0 || e > 0) && (isIntegral(a) || !isIntegral(ab)))
        return pow(base->operand(0), constant(ab));
    }
  }
  if (base->isConstant(1) && isTotal(exponent))
    return one();
  ExprRef ops[] = {base, exponent};
  return intern(ExprKind::Pow, 0, 0, 0, 0, ops);
}

} // namespace ldae::ir
