// The reference double-precision semantics of expressions: applyFunc for the
// built-ins (also used by constant folding) and evaluate(), which walks the
// DAG with an explicit stack, memoizes shared nodes, evaluates only the
// chosen branch of `if` (and short-circuits `and`/`or`), and turns every
// domain error into an Error naming the failing subexpression.
#include "ir/Evaluate.h"
#include "ir/External.h"
#include "ir/NodeMap.h"
#include "ir/Print.h"
#include "support/ModelicaErrorMessage.h"

#include <cmath>
#include <limits>
#include <vector>

namespace ldae::ir {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool isIntegerValue(double v) { return std::isfinite(v) && v == std::floor(v); }

/// Modelica's mod: a - floor(a/b)*b.
double modValue(double a, double b) { return a - std::floor(a / b) * b; }

/// Null if f(a, b) is defined, else what is wrong (for the message).
std::string domainProblem(FuncKind f, double a, double b) {
  switch (f) {
  case FuncKind::Log:
  case FuncKind::Log10:
    if (!(a > 0))
      return "logarithm of non-positive value " + printNumber(a);
    break;
  case FuncKind::Sqrt:
    if (a < 0)
      return "square root of negative value " + printNumber(a);
    break;
  case FuncKind::Asin:
  case FuncKind::Acos:
    if (a < -1 || a > 1)
      return "argument " + printNumber(a) + " outside [-1, 1]";
    break;
  case FuncKind::Mod:
    if (b == 0)
      return "modulo by zero";
    break;
  default:
    break;
  }
  return {};
}

std::string powProblem(double a, double b) {
  if (a == 0 && b < 0)
    return "division by zero";
  if (a < 0 && !isIntegerValue(b))
    return "negative base " + printNumber(a) + " with non-integer exponent " +
           printNumber(b);
  return {};
}

class Evaluator {
public:
  Evaluator(const EvalEnv &env, const NameResolver *names)
      : env_(env), names_(names) {}

  Expected<double> run(ExprRef root) {
    push(root);
    while (!stack_.empty()) {
      size_t top = stack_.size() - 1;
      ExprRef e = stack_[top].node;
      if (memo_.contains(e)) {
        stack_.pop_back();
        continue;
      }
      if (!step(top))
        return Error{error_};
    }
    return *memo_.find(root);
  }

private:
  struct Frame {
    ExprRef node;
    unsigned stage;
  };
  const EvalEnv &env_;
  const NameResolver *names_;
  std::vector<Frame> stack_;
  NodeMap<double> memo_;
  std::string error_;

  void push(ExprRef e) {
    if (!memo_.contains(e))
      stack_.push_back({e, 0});
  }
  double value(ExprRef e) const { return *memo_.find(e); }
  void done(ExprRef e, double v) {
    memo_.insert(e, v);
    stack_.pop_back();
  }
  bool fail(ExprRef e, const std::string &what) {
    error_ = what + " in '" + printLsdBrief(e, names_) + "'";
    return false;
  }

  std::string varName(VarId v) const {
    return names_ ? names_->variableName(v) : "v" + std::to_string(v);
  }

  /// Advances the frame at `top`; false on an error.
  bool step(size_t top) {
    ExprRef e = stack_[top].node;
    unsigned stage = stack_[top].stage;
    switch (e->kind()) {
    case ExprKind::Constant:
      done(e, e->constant());
      return true;
    case ExprKind::Parameter:
      if (!env_.parameter)
        return fail(e, "no value for the parameter");
      done(e, env_.parameter(e->param()));
      return true;
    case ExprKind::Variable:
      if (!env_.variable)
        return fail(e, "no value for the variable");
      done(e, env_.variable(e->varKey()));
      return true;
    case ExprKind::Time:
      done(e, env_.time);
      return true;
    case ExprKind::Pre:
      if (env_.pre)
        done(e, env_.pre(e->var()));
      else if (env_.variable)
        done(e, env_.variable({e->var(), 0}));
      else
        return fail(e, "no value for the variable");
      return true;
    case ExprKind::If:
      if (stage == 0) {
        stack_[top].stage = 1;
        push(e->operand(0));
      } else if (stage == 1) {
        stack_[top].stage = 2;
        push(value(e->operand(0)) != 0 ? e->operand(1) : e->operand(2));
      } else {
        done(e,
             value(value(e->operand(0)) != 0 ? e->operand(1) : e->operand(2)));
      }
      return true;
    case ExprKind::And:
    case ExprKind::Or: {
      // Short-circuit: stage i means operands 0..i-1 are known.
      bool isAnd = e->kind() == ExprKind::And;
      if (stage > 0) {
        bool truth = value(e->operand(stage - 1)) != 0;
        if (truth != isAnd) {
          done(e, isAnd ? 0 : 1);
          return true;
        }
      }
      if (stage == e->numOperands()) {
        done(e, isAnd ? 1 : 0);
      } else {
        stack_[top].stage = stage + 1;
        push(e->operand(stage));
      }
      return true;
    }
    default:
      break;
    }
    if (stage == 0) {
      stack_[top].stage = 1;
      for (unsigned i = e->numOperands(); i-- > 0;)
        push(e->operand(i));
      return true;
    }
    return compute(e);
  }

  /// Computes an arithmetic node whose operands are all known.
  bool compute(ExprRef e) {
    switch (e->kind()) {
    case ExprKind::Add: {
      double s = 0;
      for (ExprRef op : e->operands())
        s += value(op);
      done(e, s);
      return true;
    }
    case ExprKind::Mul: {
      double p = 1;
      for (ExprRef op : e->operands())
        p *= value(op);
      done(e, p);
      return true;
    }
    case ExprKind::Pow: {
      double a = value(e->operand(0)), b = value(e->operand(1));
      if (std::string why = powProblem(a, b); !why.empty())
        return fail(e, why);
      done(e, std::pow(a, b));
      return true;
    }
    case ExprKind::Call: {
      double a = value(e->operand(0));
      double b = e->numOperands() > 1 ? value(e->operand(1)) : 0;
      if (std::string why = domainProblem(e->func(), a, b); !why.empty())
        return fail(e, why);
      done(e, applyFunc(e->func(), a, b));
      return true;
    }
    case ExprKind::External: {
      std::vector<double> in;
      in.reserve(e->numOperands());
      for (ExprRef op : e->operands())
        in.push_back(value(op));
      const ExternalFunction &f = externalFunction(e->externalId());
      if (!f.entry)
        return fail(e, "cannot evaluate: '" + f.name + "' is not loaded");
      // Made only where the run fires its when-clause.
      if (f.impure)
        return fail(e, "'" + f.name + "' is impure: called during the run");
      double r = callExternal(e->externalId(), in.data(), e->externalOutput());
      if (std::isnan(r)) {
        std::string error = takeModelicaError();
        return fail(e, error.empty() ? "'" + f.name + "' returned NaN"
                                     : "'" + f.name + "' failed: " + error);
      }
      done(e, r);
      return true;
    }
    case ExprKind::Compare:
      done(e, applyCompare(e->compare(), value(e->operand(0)),
                           value(e->operand(1)))
                  ? 1
                  : 0);
      return true;
    case ExprKind::Not:
      done(e, value(e->operand(0)) == 0 ? 1 : 0);
      return true;
    default:
      return fail(e, "cannot evaluate");
    }
  }
};

} // namespace

double applyFunc(FuncKind f, double a, double b) {
  if (!domainProblem(f, a, b).empty())
    return kNaN;
  switch (f) {
  case FuncKind::Sin:
    return std::sin(a);
  case FuncKind::Cos:
    return std::cos(a);
  case FuncKind::Tan:
    return std::tan(a);
  case FuncKind::Asin:
    return std::asin(a);
  case FuncKind::Acos:
    return std::acos(a);
  case FuncKind::Atan:
    return std::atan(a);
  case FuncKind::Atan2:
    return std::atan2(a, b);
  case FuncKind::Sinh:
    return std::sinh(a);
  case FuncKind::Cosh:
    return std::cosh(a);
  case FuncKind::Tanh:
    return std::tanh(a);
  case FuncKind::Exp:
    return std::exp(a);
  case FuncKind::Log:
    return std::log(a);
  case FuncKind::Log10:
    return std::log10(a);
  case FuncKind::Sqrt:
    return std::sqrt(a);
  case FuncKind::Abs:
    return std::fabs(a);
  case FuncKind::Sign:
    return a > 0 ? 1.0 : a < 0 ? -1.0 : 0.0;
  case FuncKind::Min:
    return a < b ? a : b;
  case FuncKind::Max:
    return a > b ? a : b;
  case FuncKind::Floor:
    return std::floor(a);
  case FuncKind::Ceil:
    return std::ceil(a);
  case FuncKind::Mod:
    return modValue(a, b);
  }
  return kNaN;
}

bool applyCompare(CompareKind c, double a, double b) {
  switch (c) {
  case CompareKind::Lt:
    return a < b;
  case CompareKind::Le:
    return a <= b;
  case CompareKind::Gt:
    return a > b;
  case CompareKind::Ge:
    return a >= b;
  case CompareKind::Eq:
    return a == b;
  case CompareKind::Ne:
    return a != b;
  }
  return false;
}

Expected<double> evaluate(ExprRef e, const EvalEnv &env,
                          const NameResolver *names) {
  return Evaluator(env, names).run(e);
}

} // namespace ldae::ir
