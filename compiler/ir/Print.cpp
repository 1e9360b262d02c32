// Printing expressions as lsd source and in a compact debug form. lsd
// printing follows Modelica's precedence (if < or < and < not < relations <
// + - (unary minus) < * / < ^ < primaries) and restores `a - b`, `-a` and
// `a / b` from the canonical forms `a + (-1)*b` and `a * b^-1`.
#include "ir/Print.h"
#include "ir/External.h"
#include "Traverse.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace ldae::ir {

namespace {

enum Prec : int {
  PrecIf,
  PrecOr,
  PrecAnd,
  PrecNot,
  PrecRel,
  PrecAdd, // binary + - and unary minus
  PrecMul,
  PrecPow,
  PrecPrimary,
};

/// What the surrounding syntax expects: a Real, a Boolean, or either.
enum class Ctx { Any, Numeric, Boolean };

const std::unordered_set<std::string> &keywords() {
  static const std::unordered_set<std::string> words = {
      "algorithm",    "and",           "annotation",  "block",
      "break",        "class",         "connect",     "connector",
      "constant",     "constrainedby", "der",         "discrete",
      "each",         "else",          "elseif",      "elsewhen",
      "encapsulated", "end",           "enumeration", "equation",
      "expandable",   "extends",       "external",    "false",
      "final",        "flow",          "for",         "function",
      "if",           "import",        "impure",      "in",
      "initial",      "inner",         "input",       "loop",
      "model",        "not",           "operator",    "or",
      "outer",        "output",        "package",     "parameter",
      "partial",      "protected",     "public",      "pure",
      "record",       "redeclare",     "replaceable", "return",
      "stream",       "then",          "true",        "type",
      "when",         "while",         "within",      "time"};
  return words;
}

/// The coefficient of a product (its leading constant), or 1.
double coefficientOf(ExprRef mul) {
  return mul->operand(0)->isConstant() ? mul->operand(0)->constant() : 1.0;
}

/// True if `e` prints with a leading minus that a sum can turn into ` - `.
bool isNegativeTerm(ExprRef e) {
  if (e->isConstant())
    return e->constant() < 0 || std::signbit(e->constant());
  return e->kind() == ExprKind::Mul && coefficientOf(e) < 0;
}

/// `a^-k` with a constant k > 0: printed in a denominator.
bool isReciprocal(ExprRef e) {
  return e->kind() == ExprKind::Pow && e->operand(1)->isConstant() &&
         e->operand(1)->constant() < 0;
}

class LsdPrinter {
public:
  LsdPrinter(const NameResolver *names, size_t limit)
      : names_(names), limit_(limit) {}

  std::string take() {
    if (out_.size() > limit_) {
      out_.resize(limit_);
      out_ += "...";
    }
    return std::move(out_);
  }

  void print(ExprRef e, int minPrec, Ctx ctx) {
    if (out_.size() > limit_)
      return;
    if (ctx == Ctx::Numeric && e->isBoolean()) {
      // A Boolean used as a number (IR truth values are 0 and 1).
      out_ += "(if ";
      print(e, PrecOr, Ctx::Boolean);
      out_ += " then 1 else 0)";
      return;
    }
    bool parens = precOf(e, ctx) < minPrec;
    if (parens)
      out_ += '(';
    emit(e, ctx);
    if (parens)
      out_ += ')';
  }

private:
  const NameResolver *names_;
  size_t limit_;
  std::string out_;

  int precOf(ExprRef e, Ctx ctx) const {
    switch (e->kind()) {
    case ExprKind::Constant:
      if (ctx == Ctx::Boolean)
        return PrecPrimary;
      return isNegativeTerm(e) ? PrecAdd : PrecPrimary;
    case ExprKind::Add:
      return PrecAdd;
    case ExprKind::Mul:
      return coefficientOf(e) < 0 ? PrecAdd : PrecMul;
    case ExprKind::Pow:
      return isReciprocal(e) ? PrecMul : PrecPow;
    case ExprKind::If:
      return names_ && names_->homotopyOf(e) ? PrecPrimary : PrecIf;
    case ExprKind::Compare:
      return e->noEvent() ? PrecPrimary : PrecRel;
    case ExprKind::And:
      return PrecAnd;
    case ExprKind::Or:
      return PrecOr;
    case ExprKind::Not:
      return PrecNot;
    default:
      return PrecPrimary;
    }
  }

  void emitName(const std::string &name) { out_ += printIdentifier(name); }

  void emit(ExprRef e, Ctx ctx) {
    switch (e->kind()) {
    case ExprKind::Constant:
      if (ctx == Ctx::Boolean)
        out_ += e->constant() != 0 ? "true" : "false";
      else
        out_ += printNumber(e->constant());
      return;
    case ExprKind::Parameter:
      if (names_ && names_->verbatimParameter(e->param()))
        out_ += names_->parameterName(e->param());
      else if (names_)
        emitName(names_->parameterName(e->param()));
      else
        out_ += "p" + std::to_string(e->param());
      return;
    case ExprKind::Variable:
      for (unsigned k = 0; k < e->order(); ++k)
        out_ += "der(";
      emitVariable(e->var());
      out_.append(e->order(), ')');
      return;
    case ExprKind::Time:
      out_ += "time";
      return;
    case ExprKind::Pre:
      out_ += "pre(";
      emitVariable(e->var());
      out_ += ')';
      return;
    case ExprKind::Add:
      emitSum(e);
      return;
    case ExprKind::Mul:
      emitProduct(e, false);
      return;
    case ExprKind::Pow:
      if (isReciprocal(e))
        emitProduct(e, false);
      else
        emitPower(e->operand(0), e->operand(1));
      return;
    case ExprKind::Call:
      out_ += funcName(e->func());
      emitArguments(e);
      return;
    case ExprKind::External: {
      const ExternalFunction &f = externalFunction(e->externalId());
      out_ += f.name;
      if (f.numOutputs > 1)
        out_ += "[" + std::to_string(e->externalOutput() + 1) + "]";
      // A run-time impure call's last two inputs (the previous impure
      // call, the time: frontend/ExternalFunctions.cpp) are ldaec's, not
      // the model's; printed, each call would repeat every earlier one.
      emitArguments(e, f.impure && e->numOperands() >= 2
                           ? e->numOperands() - 2
                           : e->numOperands());
      return;
    }
    case ExprKind::If:
      if (const auto *h = names_ ? names_->homotopyOf(e) : nullptr) {
        out_ += "homotopy(actual = ";
        print(h->first, PrecIf, Ctx::Numeric);
        out_ += ", simplified = ";
        print(h->second, PrecIf, Ctx::Numeric);
        out_ += ')';
        return;
      }
      out_ += "if ";
      print(e->operand(0), PrecOr, Ctx::Boolean);
      out_ += " then ";
      print(e->operand(1), PrecOr, ctx);
      out_ += " else ";
      print(e->operand(2), PrecOr, ctx);
      return;
    case ExprKind::Compare:
      if (e->noEvent())
        out_ += "noEvent(";
      print(e->operand(0), PrecAdd, Ctx::Numeric);
      out_ += ' ';
      out_ += compareSymbol(e->compare());
      out_ += ' ';
      print(e->operand(1), PrecAdd, Ctx::Numeric);
      if (e->noEvent())
        out_ += ')';
      return;
    case ExprKind::And:
    case ExprKind::Or: {
      bool isAnd = e->kind() == ExprKind::And;
      for (unsigned i = 0; i < e->numOperands(); ++i) {
        if (i)
          out_ += isAnd ? " and " : " or ";
        print(e->operand(i), isAnd ? PrecNot : PrecAnd, Ctx::Boolean);
      }
      return;
    }
    case ExprKind::Not:
      out_ += "not ";
      print(e->operand(0), PrecRel, Ctx::Boolean);
      return;
    }
  }

  void emitVariable(VarId v) {
    if (names_ && names_->verbatimVariable(v))
      out_ += names_->variableName(v);
    else if (names_)
      emitName(names_->variableName(v));
    else
      out_ += "v" + std::to_string(v);
  }

  void emitSum(ExprRef e) {
    // Terms in canonical order with the constant last; a positive term
    // leads when there is one (`y - x` rather than `-x + y`).
    std::vector<ExprRef> terms;
    for (ExprRef t : e->operands())
      if (!t->isConstant())
        terms.push_back(t);
    for (ExprRef t : e->operands())
      if (t->isConstant())
        terms.push_back(t);
    auto positive = std::find_if(terms.begin(), terms.end(),
                                 [](ExprRef t) { return !isNegativeTerm(t); });
    if (positive != terms.end())
      std::rotate(terms.begin(), positive, positive + 1);
    for (size_t i = 0; i < terms.size(); ++i) {
      ExprRef t = terms[i];
      bool negative = isNegativeTerm(t);
      if (i)
        out_ += negative ? " - " : " + ";
      else if (negative)
        out_ += '-';
      emitMagnitude(t, negative);
    }
  }

  /// A term of a sum without its sign (when `negative`), as a `term` of the
  /// grammar (a product or tighter).
  void emitMagnitude(ExprRef t, bool negative) {
    if (!negative) {
      print(t, PrecMul, Ctx::Numeric);
    } else if (t->isConstant()) {
      out_ += printNumber(-t->constant());
    } else {
      emitProduct(t, true); // a product prints at PrecMul without its sign
    }
  }

  /// `(a, b, ...)`: a call's operands.
  void emitArguments(ExprRef e) { emitArguments(e, e->numOperands()); }
  /// The first `count` operands of `e` as an argument list.
  void emitArguments(ExprRef e, unsigned count) {
    out_ += '(';
    for (unsigned i = 0; i < count; ++i) {
      if (i)
        out_ += ", ";
      print(e->operand(i), PrecIf, Ctx::Numeric);
    }
    out_ += ')';
  }

  void emitPower(ExprRef base, ExprRef exponent) {
    print(base, PrecPrimary, Ctx::Numeric);
    out_ += '^';
    print(exponent, PrecPrimary, Ctx::Numeric);
  }

  /// A product (or a lone reciprocal `x^-k`) as `c * a * b / d / e^2`;
  /// `absolute` drops a negative coefficient's sign (the caller printed it).
  void emitProduct(ExprRef e, bool absolute) {
    double coef = 1;
    std::span<const ExprRef> factors(&e, 1);
    if (e->kind() == ExprKind::Mul) {
      coef = coefficientOf(e);
      factors = e->operands().subspan(e->operand(0)->isConstant() ? 1 : 0);
    }
    if (coef < 0) {
      if (!absolute)
        out_ += '-';
      coef = -coef;
    }
    std::vector<ExprRef> numerator, denominator;
    for (ExprRef f : factors)
      (isReciprocal(f) ? denominator : numerator).push_back(f);

    // A coefficient that is the reciprocal of a shorter number reads as a
    // division: x * 0.5 prints `x / 2` (and reads back as the same bits).
    std::string coefText, coefDivisor;
    if (coef != 1) {
      double d = 1 / coef;
      std::string direct = printNumber(coef), inverse = printNumber(d);
      if (1 / d == coef && inverse.size() < direct.size())
        coefDivisor = inverse;
      else
        coefText = direct;
    }
    bool first = true;
    auto sep = [&] {
      if (!first)
        out_ += " * ";
      first = false;
    };
    if (!coefText.empty()) {
      sep();
      out_ += coefText;
    }
    for (ExprRef f : numerator) {
      sep();
      print(f, PrecPow, Ctx::Numeric);
    }
    if (first)
      out_ += '1';
    if (!coefDivisor.empty())
      out_ += " / " + coefDivisor;
    for (ExprRef f : denominator) {
      out_ += " / ";
      double k = -f->operand(1)->constant();
      if (k == 1) {
        print(f->operand(0), PrecPow, Ctx::Numeric);
      } else {
        print(f->operand(0), PrecPrimary, Ctx::Numeric);
        out_ += '^';
        out_ += printNumber(k);
      }
    }
  }
};

class DebugPrinter {
public:
  DebugPrinter(ExprRef root, const NameResolver *names) : names_(names) {
    // Nodes used more than once print their body once, then `#id`.
    ExprRef roots[] = {root};
    postOrder(roots, [&](ExprRef n) {
      for (ExprRef op : n->operands())
        ++uses_[op];
    });
  }

  void print(ExprRef e) {
    switch (e->kind()) {
    case ExprKind::Constant:
      out_ += printNumber(e->constant());
      return;
    case ExprKind::Parameter:
      out_ += names_ ? names_->parameterName(e->param())
                     : "p" + std::to_string(e->param());
      return;
    case ExprKind::Variable:
    case ExprKind::Pre: {
      std::string name = names_ ? names_->variableName(e->var())
                                : "v" + std::to_string(e->var());
      if (e->kind() == ExprKind::Pre)
        out_ += "pre(" + name + ")";
      else if (e->order() == 0)
        out_ += name;
      else
        out_ += name + "'" + std::to_string(e->order());
      return;
    }
    case ExprKind::Time:
      out_ += "time";
      return;
    default:
      break;
    }
    bool shared = uses_[e] > 1;
    if (shared) {
      out_ += '#' + std::to_string(e->id());
      if (!printed_.insert(e).second)
        return;
      out_ += '=';
    }
    out_ += '(';
    out_ += opName(e);
    for (ExprRef op : e->operands()) {
      out_ += ' ';
      print(op);
    }
    out_ += ')';
  }

  std::string take() { return std::move(out_); }

private:
  const NameResolver *names_;
  std::unordered_map<ExprRef, unsigned> uses_;
  std::unordered_set<ExprRef> printed_;
  std::string out_;

  static std::string opName(ExprRef e) {
    switch (e->kind()) {
    case ExprKind::Add:
      return "+";
    case ExprKind::Mul:
      return "*";
    case ExprKind::Pow:
      return "^";
    case ExprKind::Call:
      return funcName(e->func());
    case ExprKind::External:
      return externalFunction(e->externalId()).name;
    case ExprKind::If:
      return "if";
    case ExprKind::Compare:
      return compareSymbol(e->compare());
    case ExprKind::And:
      return "and";
    case ExprKind::Or:
      return "or";
    case ExprKind::Not:
      return "not";
    default:
      return "?";
    }
  }
};

} // namespace

namespace {

/// `text` between `quote` characters, escaping the quote and backslash.
std::string quoteWith(const std::string &text, char quote) {
  std::string out(1, quote);
  for (char c : text) {
    if (c == quote || c == '\\')
      out += '\\';
    out += c;
  }
  return out + quote;
}

} // namespace

std::string printNumber(double v) {
  if (std::isnan(v))
    return "nan";
  if (std::isinf(v))
    return v > 0 ? "inf" : "-inf";
  if (v == 0)
    return "0";
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

std::string printIdentifier(const std::string &name) {
  bool plain =
      !name.empty() &&
      (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
      std::all_of(name.begin(), name.end(),
                  [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) ||
                           c == '_';
                  }) &&
      !keywords().count(name);
  return plain ? name : quoteWith(name, '\'');
}

std::string printString(const std::string &text) {
  return quoteWith(text, '"');
}

std::string printLsd(ExprRef e, const NameResolver *names) {
  LsdPrinter p(names, SIZE_MAX - 4);
  p.print(e, PrecIf, Ctx::Any);
  return p.take();
}

std::string printLsdBrief(ExprRef e, const NameResolver *names,
                          size_t maxChars) {
  LsdPrinter p(names, maxChars);
  p.print(e, PrecIf, Ctx::Any);
  return p.take();
}

std::string printDebug(ExprRef e, const NameResolver *names) {
  DebugPrinter p(e, names);
  p.print(e);
  return p.take();
}

} // namespace ldae::ir
