// Calls: the built-in functions and operators of LANGUAGE.md (der by the
// chain rule, pre, reductions, size, array constructors, math functions)
// and the dispatch to user functions, which Inline.cpp inlines.
#include "frontend/Concatenate.h"
#include "frontend/ExternalObject.h"
#include "frontend/Flattener.h"

#include "ir/Query.h"
#include "ir/Substitute.h"

#include <cmath>
#include <limits>

namespace ldae::frontend {
namespace {

struct MathFn {
  const char *name;
  ir::FuncKind kind;
};
constexpr MathFn kMathFns[] = {
    {"sin", ir::FuncKind::Sin},     {"cos", ir::FuncKind::Cos},
    {"tan", ir::FuncKind::Tan},     {"asin", ir::FuncKind::Asin},
    {"acos", ir::FuncKind::Acos},   {"atan", ir::FuncKind::Atan},
    {"atan2", ir::FuncKind::Atan2}, {"sinh", ir::FuncKind::Sinh},
    {"cosh", ir::FuncKind::Cosh},   {"tanh", ir::FuncKind::Tanh},
    {"exp", ir::FuncKind::Exp},     {"log", ir::FuncKind::Log},
    {"log10", ir::FuncKind::Log10}, {"sqrt", ir::FuncKind::Sqrt},
    {"abs", ir::FuncKind::Abs},     {"sign", ir::FuncKind::Sign},
    {"floor", ir::FuncKind::Floor}, {"ceil", ir::FuncKind::Ceil},
    {"mod", ir::FuncKind::Mod},     {"min", ir::FuncKind::Min},
    {"max", ir::FuncKind::Max},
};

const MathFn *mathFn(const std::string &name) {
  for (const MathFn &f : kMathFns)
    if (name == f.name)
      return &f;
  return nullptr;
}

/// Names handled here rather than by lookup; the unsupported ones get a
/// clear message instead of "undefined name".
bool isBuiltinName(const std::string &n) {
  static const char *names[] = {
      "der", "pre", "initial", "terminal", "noEvent", "smooth", "homotopy",
      "sum", "product", "size", "ndims", "zeros", "ones", "fill", "identity",
      "linspace", "transpose", "vector", "scalar", "cross", "diagonal", "div",
      "rem", "integer", "Integer", "sample", "edge", "change", "delay",
      "reinit", "assert", "terminate", "cardinality", "semiLinear", "String",
      "abs", "sign", "sqrt", "min", "max", "mod", "floor", "ceil", "cat",
      "getInstanceName",
  };
  for (const char *b : names)
    if (n == b)
      return true;
  return mathFn(n) != nullptr;
}

/// `Modelica.Math.sin` and `Modelica.Constants` style names map to the
/// built-ins, so models written against the MSL's math package compile.
std::string builtinNameOf(const ast::Expr &call) {
  // `.sin(u)`: MSL's Modelica.Math.sin calls the built-in by its global
  // name.
  if (call.parts.size() == 1)
    return call.parts[0].name;
  if (call.parts.size() >= 3 && call.parts[0].name == "Modelica" &&
      call.parts[1].name == "Math" && mathFn(call.parts.back().name))
    return call.parts.back().name;
  return "";
}

} // namespace

/// min and max of no elements (MLS 10.3.4.1: the greatest, and the
/// least, value of the type; Real's largest finite values here, as
/// MSL's MinMax with nu = 0 gives them).
ir::ExprRef Flattener::emptyMinMax(const std::string &name) {
  double greatest = std::numeric_limits<double>::max();
  return ctx().constant(name == "min" ? greatest : -greatest);
}

std::optional<std::vector<Value>>
Flattener::lowerCallOutputs(const ast::Expr &call, const Scope &scope,
                            Env *env) {
  if (call.partialApplication) {
    report(DiagId::ErrUnsupported, SourceRange{call.loc, call.length},
           {"a function value `function " + call.text +
            "(...)` other than as an argument for an input of a function type"});
    return std::nullopt;
  }
  // An input of a function type called (MLS 12.4.2.1): its function,
  // with the inputs its partial application bound.
  if (env && call.parts.size() == 1 && !call.global)
    if (const FunctionValue *f = env->findFunction(call.parts[0].name)) {
      FunctionValue value = *f; // the environment may grow while inlining
      std::optional<FunctionParts> parts =
          functionParts(*value.fn, SourceRange{call.loc, call.length});
      if (!parts)
        return std::nullopt;
      std::vector<CallArgument> given;
      for (const ast::Component *c : parts->comps) {
        if (c->prefix.causality != ast::Causality::Input)
          continue;
        given.emplace_back();
        for (const auto &[name, v] : value.bound)
          if (name == c->name) {
            given.back().value = v;
            given.back().preBound = true;
          }
      }
      return inlineCall(*value.fn, call, scope, env, &given);
    }
  std::string builtin = builtinNameOf(call);
  if (builtin.empty() || !isBuiltinName(builtin)) {
    ast::Name fname = call.calleeName();
    uint32_t file = scope.cls ? scope.cls->file : call.loc.file;
    LexicalHit hit = classes_.lookup(fname.parts[0], call.global ? nullptr : scope.cls, file);
    if (!hit.cls) {
      std::vector<std::string> names;
      classes_.visibleNames(scope.cls, file, names);
      for (const MathFn &f : kMathFns)
        names.push_back(f.name);
      std::string best = closestName(fname.parts[0], names);
      if (best.empty())
        report(DiagId::ErrUndefinedFunction, SourceRange{fname.loc, fname.length},
               {fname.str()});
      else
        report(DiagId::ErrUndefinedFunctionSuggest,
               SourceRange{fname.loc, fname.length}, {fname.str(), best});
      return std::nullopt;
    }
    const ast::ClassDef *fn = classes_.resolveClass(fname, call.global ? nullptr : scope.cls, file);
    if (!fn)
      return std::nullopt;
    // A short definition `function f2 = f;` names the same function.
    for (unsigned guard = 0; fn && fn->isShort && guard < 16; ++guard)
      fn = classes_.resolveClass(fn->shortBase, fn->parent, fn->file);
    if (!fn)
      return std::nullopt;
    // `Table(...)` of an external object class calls its constructor.
    if (fn->kind != ast::ClassKind::Function && isExternalObject(*fn))
      if (const ast::ClassDef *ctor = externalObjectConstructor(*fn))
        return inlineCall(*ctor, call, scope, env);
    if (fn->kind != ast::ClassKind::Function) {
      report(DiagId::ErrNotAFunction, SourceRange{fname.loc, fname.length},
             {fname.str(), ast::classKindName(fn->kind)});
      return std::nullopt;
    }
    // The tool's part of the library (ModelicaServices) is ldaec's.
    if (isLoadResource(*fn)) {
      std::optional<Value> path = lowerLoadResource(call, scope, env);
      if (!path)
        return std::nullopt;
      return std::vector<Value>{std::move(*path)};
    }
    return inlineCall(*fn, call, scope, env);
  }
  std::optional<Value> v = lowerCall(call, scope, env);
  if (!v)
    return std::nullopt;
  return std::vector<Value>{std::move(*v)};
}

ir::ExprRef Flattener::eventInput(ir::EventInput kind, const std::string &text,
                                  ir::ExprRef start, ir::ExprRef interval,
                                  SourceLoc loc) {
  if (std::optional<ir::VarId> v = model_->findVariable(text))
    return ctx().var(*v);
  ir::Variable v;
  v.name = text;
  v.loc = loc; // the first call
  v.isDiscrete = true;
  v.isBoolean = true;
  v.input = kind;
  v.sampleStart = start;
  v.sampleInterval = interval;
  return ctx().var(model_->addVariable(std::move(v)));
}

/// The runtime finds the parameter by this name (LDAE_HOMOTOPY_LAMBDA of
/// the model ABI).
ir::ParamId Flattener::homotopyLambda() {
  if (auto p = model_->findParameter("homotopy.lambda"))
    return *p;
  ir::Parameter p;
  p.name = "homotopy.lambda";
  p.value = 1;
  p.generated = true;
  return model_->addParameter(std::move(p));
}

std::optional<Value> Flattener::lowerCall(const ast::Expr &call,
                                          const Scope &scope, Env *env) {
  std::string name = builtinNameOf(call);
  if (name.empty() || !isBuiltinName(name)) {
    auto outs = lowerCallOutputs(call, scope, env);
    if (!outs)
      return std::nullopt;
    if (outs->empty()) {
      report(DiagId::ErrFunctionNoOutput, SourceRange{call.loc, call.length},
             {call.text});
      return std::nullopt;
    }
    return std::move((*outs)[0]);
  }
  ir::ExprContext &c = ctx();
  SourceRange where{call.loc, call.length};

  // Reductions with iterators: sum(e for i in 1:n), product, min, max.
  if (!call.iterators.empty()) {
    if (name != "sum" && name != "product" && name != "min" && name != "max") {
      report(DiagId::ErrUnsupported, where, {"'for' in a call to '" + name + "'"});
      return std::nullopt;
    }
    if (call.args.size() != 1) {
      report(DiagId::ErrCallArgCount, where, {name, "1", std::to_string(call.args.size())});
      return std::nullopt;
    }
    Env local{env, {}};
    std::optional<Value> acc;
    std::function<bool(size_t)> iterate = [&](size_t k) -> bool {
      if (k == call.iterators.size()) {
        std::optional<Value> v = lower(*call.args[0].value, scope, &local);
        if (!v || v->isString)
          return false;
        if (!acc) {
          acc = std::move(v);
          return true;
        }
        auto combined = [&](ir::ExprRef a, ir::ExprRef b) {
          if (name == "sum")
            return c.add(a, b);
          if (name == "product")
            return c.mul(a, b);
          return c.call(name == "min" ? ir::FuncKind::Min : ir::FuncKind::Max, a, b);
        };
        if (v->shape != acc->shape) {
          report(DiagId::ErrShapeMismatch, where,
                 {name, describeShape(acc->shape), describeShape(v->shape)});
          return false;
        }
        for (size_t i = 0; i < acc->elems.size(); ++i)
          acc->elems[i] = combined(acc->elems[i], v->elems[i]);
        return true;
      }
      auto values = iteratorValues(call.iterators[k], scope, &local);
      if (!values)
        return false;
      for (double x : *values) {
        local.set(call.iterators[k].name, Value::scalar(c.constant(x)));
        if (!iterate(k + 1) || overBudget())
          return false;
      }
      return true;
    };
    if (!iterate(0))
      return std::nullopt;
    if (!acc) {
      if (name == "sum")
        return Value::scalar(c.zero());
      if (name == "product")
        return Value::scalar(c.one());
      return Value::scalar(emptyMinMax(name));
    }
    return acc;
  }

  if (name == "String")
    return lowerStringCall(call, scope, env);
  if (name == "cardinality")
    return lowerCardinality(call, scope, env);
  for (const ast::Arg &a : call.args)
    if (!a.name.empty() && name != "homotopy" && name != "assert") {
      report(DiagId::ErrNamedArgBuiltin, SourceRange{a.value->loc, a.value->length},
             {name, a.name});
      return std::nullopt;
    }
  auto argCount = [&](size_t lo, size_t hi) {
    if (call.args.size() >= lo && call.args.size() <= hi)
      return true;
    report(DiagId::ErrCallArgCount, where,
           {name, lo == hi ? std::to_string(lo)
                           : std::to_string(lo) + " to " + std::to_string(hi),
            std::to_string(call.args.size())});
    return false;
  };
  std::vector<Value> args;
  auto lowerArgs = [&]() {
    for (const ast::Arg &a : call.args) {
      std::optional<Value> v = lower(*a.value, scope, env);
      if (!v)
        return false;
      if (v->isString) {
        report(DiagId::ErrStringOperand,
               SourceRange{a.value->loc, a.value->length}, {name});
        return false;
      }
      args.push_back(std::move(*v));
    }
    return true;
  };
  auto intArg = [&](size_t i) -> std::optional<int64_t> {
    return evalInteger(*call.args[i].value, scope, env,
                       "argument " + std::to_string(i + 1) + " of '" + name + "'");
  };

  if (name == "der") {
    if (!argCount(1, 2) || !lowerArgs())
      return std::nullopt;
    int64_t times = 1;
    if (args.size() == 2) {
      std::optional<int64_t> n = intArg(1);
      if (!n || *n < 1 || *n > 16)
        return std::nullopt;
      times = *n;
    }
    Value r = args[0];
    for (int64_t t = 0; t < times; ++t)
      for (ir::ExprRef &x : r.elems)
        x = differentiator().timeDerivative(x);
    return r;
  }
  if (name == "pre") {
    // In a model's algorithm section a name the section assigns is a local
    // (ModelAlgorithms.cpp); pre() of it is the variable's, while loop
    // indices stay visible.
    if (algorithmLocals_ && env) {
      if (!argCount(1, 1))
        return std::nullopt;
      Env visible = *env;
      std::erase_if(visible.vars, [&](const auto &var) {
        return std::find(algorithmLocals_->begin(), algorithmLocals_->end(),
                         var.first) != algorithmLocals_->end();
      });
      std::optional<Value> v = lower(*call.args[0].value, scope, &visible);
      if (!v)
        return std::nullopt;
      args.push_back(std::move(*v));
    } else if (!argCount(1, 1) || !lowerArgs()) {
      return std::nullopt;
    }
    Value r = args[0];
    for (ir::ExprRef &x : r.elems) {
      if (x->kind() == ir::ExprKind::Parameter || x->isConstant())
        continue; // pre of a parameter is the parameter
      if (x->kind() != ir::ExprKind::Variable || x->order() != 0) {
        report(DiagId::ErrPreNotVariable, where, {});
        return std::nullopt;
      }
      x = c.pre(x->var());
    }
    return r;
  }
  if (name == "noEvent") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    return map1Value(args[0],
                     [&](ir::ExprRef x) { return ir::withNoEvent(c, x); });
  }
  if (name == "smooth") {
    // smooth(0, e) may jump, so its relations generate events as e's;
    // from order 1 on it is continuous across them: like noEvent.
    if (!argCount(2, 2))
      return std::nullopt;
    std::optional<int64_t> order = intArg(0);
    if (!order)
      return std::nullopt;
    std::optional<Value> v = lower(*call.args[1].value, scope, env);
    if (!v || *order < 1)
      return v;
    return map1Value(*v, [&](ir::ExprRef x) { return ir::withNoEvent(c, x); });
  }
  if (name == "getInstanceName") {
    // MLS 3.7.4: the simulated model's name and the instance's path
    // ("Vehicle.engine.controller"); in a function, unspecified: the
    // model's name.
    if (!argCount(0, 0))
      return std::nullopt;
    std::string path = scope.inst ? scope.inst->path : "";
    return Value::string(model_->name + (path.empty() ? "" : "." + path));
  }
  if (name == "initial" || name == "terminal") {
    if (!argCount(0, 0))
      return std::nullopt;
    return Value::scalar(eventInput(
        name == "initial" ? ir::EventInput::Initial : ir::EventInput::Terminal,
        name + "()", nullptr, nullptr, call.loc));
  }
  if (name == "sample") {
    if (!argCount(2, 2) || !lowerArgs())
      return std::nullopt;
    for (size_t i = 0; i < 2; ++i)
      if (!args[i].isScalar()) {
        report(DiagId::ErrExpectedScalar,
               SourceRange{call.args[i].value->loc, call.args[i].value->length},
               {"argument of 'sample'", describeShape(args[i].shape)});
        return std::nullopt;
      }
    ir::ExprRef start = args[0].scalarExpr(), interval = args[1].scalarExpr();
    std::string text = "sample(" + ir::printLsd(start, model_.get()) + ", " +
                       ir::printLsd(interval, model_.get()) + ")";
    return Value::scalar(
        eventInput(ir::EventInput::Sample, text, start, interval, call.loc));
  }
  if (name == "delay") {
    // delay(e, d[, dMax]): a discrete input the runtime sets from e's
    // history (docs/events.md, "delay()"). d of parameters only: with a
    // d that varies, the delayed value would jump where t - d(t) crosses
    // an event of e, a crossing no time event gives.
    if (!argCount(2, 3) || !lowerArgs())
      return std::nullopt;
    for (size_t i = 0; i < args.size(); ++i)
      if (!args[i].isScalar()) {
        report(DiagId::ErrExpectedScalar,
               SourceRange{call.args[i].value->loc, call.args[i].value->length},
               {"argument of 'delay'", describeShape(args[i].shape)});
        return std::nullopt;
      }
    auto ofParameters = [](ir::ExprRef e) {
      return ir::freeVariables(e).empty() && !ir::dependsOnTime(e);
    };
    for (size_t i = 1; i < args.size(); ++i) {
      ir::ExprRef e = args[i].scalarExpr();
      if (ofParameters(e))
        continue;
      const ast::Expr &a = *call.args[i].value;
      report(i == 2 ? DiagId::ErrDelayMaxNotParameter
             : args.size() == 3 ? DiagId::ErrDelayTimeVarying
                                : DiagId::ErrDelayTimeNotParameter,
             SourceRange{a.loc, a.length}, {ir::printLsd(e, model_.get())});
      return std::nullopt;
    }
    std::string text = "delay(";
    for (size_t i = 0; i < args.size(); ++i)
      text += (i ? ", " : "") + ir::printLsd(args[i].scalarExpr(), model_.get());
    text += ")";
    if (std::optional<ir::VarId> v = model_->findVariable(text))
      return Value::scalar(c.var(*v));
    ir::Variable v;
    v.name = text;
    v.loc = call.loc;
    v.isDiscrete = true;
    v.input = ir::EventInput::Delay;
    v.delayed = args[0].scalarExpr();
    v.delayTime = args[1].scalarExpr();
    v.delayMax = args.size() == 3 ? args[2].scalarExpr() : nullptr;
    return Value::scalar(c.var(model_->addVariable(std::move(v))));
  }
  if (name == "edge" || name == "change") {
    // edge(b) = b and not pre(b); change(v) = v <> pre(v).
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    Value r = args[0];
    for (ir::ExprRef &x : r.elems) {
      if (x->kind() != ir::ExprKind::Variable || x->order() != 0) {
        report(DiagId::ErrArgNotVariable, where, {name});
        return std::nullopt;
      }
      ir::ExprRef pre = c.pre(x->var());
      x = name == "edge"
              ? c.logicalAnd(c.compare(ir::CompareKind::Ne, x, c.zero()),
                             c.compare(ir::CompareKind::Eq, pre, c.zero()))
              : c.compare(ir::CompareKind::Ne, x, pre);
    }
    return r;
  }
  if (name == "homotopy") {
    // homotopy(actual, simplified): `actual` in the run; with
    // homotopy.lambda < 1 (set only by the runtime's continuation when the
    // initialization fails from the start values) the blend
    // lambda*actual + (1 - lambda)*simplified. At lambda = 1 only `actual`
    // is evaluated.
    const ast::Expr *actual = nullptr, *simplified = nullptr;
    for (size_t i = 0; i < call.args.size(); ++i) {
      const ast::Arg &a = call.args[i];
      if (a.name == "actual" || (a.name.empty() && i == 0))
        actual = a.value.get();
      else if (a.name == "simplified" || (a.name.empty() && i == 1))
        simplified = a.value.get();
    }
    if (!actual || call.args.size() > 2) {
      report(DiagId::ErrCallArgCount, where,
             {name, "2", std::to_string(call.args.size())});
      return std::nullopt;
    }
    auto a = lower(*actual, scope, env);
    if (!a || !simplified)
      return a;
    auto s = lower(*simplified, scope, env);
    if (!s)
      return std::nullopt;
    if (a->shape != s->shape || a->isString || s->isString) {
      report(DiagId::ErrShapeMismatch, where,
             {name, describeShape(a->shape), describeShape(s->shape)});
      return std::nullopt;
    }
    ir::ExprRef lambda = c.param(homotopyLambda());
    ir::ExprRef atOne = c.compare(ir::CompareKind::Eq, lambda, c.one());
    for (size_t i = 0; i < a->elems.size(); ++i) {
      ir::ExprRef blend = c.ifThenElse(
          atOne, a->elems[i],
          c.add(c.mul(lambda, a->elems[i]),
                c.mul(c.sub(c.one(), lambda), s->elems[i])));
      model_->homotopies.emplace(blend,
                                 std::make_pair(a->elems[i], s->elems[i]));
      a->elems[i] = blend;
    }
    return a;
  }
  if (const MathFn *f = mathFn(name)) {
    unsigned arity = ir::funcArity(f->kind);
    if ((name == "min" || name == "max") && call.args.size() == 1) {
      if (!lowerArgs())
        return std::nullopt;
      if (args[0].elems.empty())
        return Value::scalar(emptyMinMax(name));
      ir::ExprRef acc = args[0].elems[0];
      for (size_t i = 1; i < args[0].elems.size(); ++i)
        acc = c.call(f->kind, acc, args[0].elems[i]);
      return Value::scalar(acc);
    }
    if (!argCount(arity, arity) || !lowerArgs())
      return std::nullopt;
    if (arity == 1)
      return map1Value(args[0], [&](ir::ExprRef x) { return c.call(f->kind, x); });
    return map2Value(args[0], args[1],
                     [&](ir::ExprRef x, ir::ExprRef y) { return c.call(f->kind, x, y); },
                     call, name.c_str());
  }
  if (name == "div" || name == "rem") {
    if (!argCount(2, 2) || !lowerArgs())
      return std::nullopt;
    auto truncDiv = [&](ir::ExprRef x, ir::ExprRef y) {
      ir::ExprRef q = c.div(x, y);
      return c.mul(c.call(ir::FuncKind::Sign, q),
                   c.call(ir::FuncKind::Floor, c.call(ir::FuncKind::Abs, q)));
    };
    if (name == "div")
      return map2Value(args[0], args[1], truncDiv, call, "div");
    return map2Value(args[0], args[1],
                     [&](ir::ExprRef x, ir::ExprRef y) {
                       return c.sub(x, c.mul(truncDiv(x, y), y));
                     },
                     call, "rem");
  }
  if (name == "integer" || name == "Integer") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    return map1Value(args[0], [&](ir::ExprRef x) { return c.call(ir::FuncKind::Floor, x); });
  }
  if (name == "sum" || name == "product") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    if (name == "sum")
      return Value::scalar(c.add(args[0].elems));
    return Value::scalar(c.mul(args[0].elems));
  }
  // The shape of size()'s and ndims()'s argument: a function's local
  // has one before it is assigned (`Real den1[size(cr, 1)]` of an output
  // cr, in MSL's filter functions).
  auto argShape = [&]() -> std::optional<std::vector<int64_t>> {
    const ast::Expr &a = *call.args[0].value;
    if (env && !a.global && a.kind == ast::ExprKind::Ref &&
        a.parts.size() == 1 && a.parts[0].subscripts.empty())
      if (Value *local = env->find(a.parts[0].name))
        if (!local->isString)
          return local->shape;
    if (!lowerArgs())
      return std::nullopt;
    return args[0].shape;
  };
  if (name == "size") {
    if (!argCount(1, 2))
      return std::nullopt;
    std::optional<std::vector<int64_t>> argShapeValue = argShape();
    if (!argShapeValue)
      return std::nullopt;
    const std::vector<int64_t> &shape = *argShapeValue;
    if (args.size() == 1) {
      Value r;
      r.shape.push_back(static_cast<int64_t>(shape.size()));
      for (int64_t d : shape)
        r.elems.push_back(c.constant(static_cast<double>(d)));
      return r;
    }
    std::optional<int64_t> k = intArg(1);
    if (!k)
      return std::nullopt;
    if (*k < 1 || *k > static_cast<int64_t>(shape.size())) {
      report(DiagId::ErrSizeDimension, where,
             {std::to_string(*k), std::to_string(shape.size())});
      return std::nullopt;
    }
    return Value::scalar(c.constant(static_cast<double>(shape[*k - 1])));
  }
  if (name == "ndims") {
    if (!argCount(1, 1))
      return std::nullopt;
    std::optional<std::vector<int64_t>> shape = argShape();
    if (!shape)
      return std::nullopt;
    return Value::scalar(c.constant(static_cast<double>(shape->size())));
  }
  if (name == "cat") {
    // cat(k, A, B, ...) joins along dimension k (MLS 10.4.2).
    if (!argCount(2, std::numeric_limits<size_t>::max()) || !lowerArgs())
      return std::nullopt;
    std::optional<int64_t> k = intArg(0);
    if (!k)
      return std::nullopt;
    std::vector<Value> parts(args.begin() + 1, args.end());
    size_t ndims = parts[0].shape.size();
    if (*k < 1 || static_cast<size_t>(*k) > ndims) {
      report(DiagId::ErrIndexOutOfRange, where,
             {fmtInteger(static_cast<double>(*k)), "cat", std::to_string(ndims)});
      return std::nullopt;
    }
    std::pair<std::string, std::string> mismatch;
    std::optional<Value> r =
        concatenate(parts, static_cast<size_t>(*k - 1), mismatch);
    if (!r)
      report(DiagId::ErrShapeMismatch, where,
             {"cat", mismatch.first, mismatch.second});
    return r;
  }
  if (name == "zeros" || name == "ones" || name == "fill") {
    size_t first = name == "fill" ? 1 : 0;
    if (!argCount(first + 1, first + 4))
      return std::nullopt;
    Value fillValue = Value::scalar(name == "ones" ? c.one() : c.zero());
    if (name == "fill") {
      std::optional<Value> v = lower(*call.args[0].value, scope, env);
      if (!v || v->isString)
        return std::nullopt;
      fillValue = *v;
    }
    Value r;
    int64_t total = 1;
    for (size_t i = first; i < call.args.size(); ++i) {
      std::optional<int64_t> n = intArg(i);
      if (!n)
        return std::nullopt;
      if (*n < 0 || (*n > 0 && total > kMaxArrayElements / *n)) {
        report(DiagId::ErrArrayTooLarge, where,
               {name, std::to_string(kMaxArrayElements)});
        return std::nullopt;
      }
      total *= *n;
      r.shape.push_back(*n);
    }
    r.shape.insert(r.shape.end(), fillValue.shape.begin(), fillValue.shape.end());
    for (int64_t i = 0; i < total; ++i)
      r.elems.insert(r.elems.end(), fillValue.elems.begin(), fillValue.elems.end());
    return r;
  }
  if (name == "identity") {
    if (!argCount(1, 1))
      return std::nullopt;
    std::optional<int64_t> n = intArg(0);
    if (!n || *n < 0 || *n > 4096)
      return std::nullopt;
    Value r;
    r.shape = {*n, *n};
    for (int64_t i = 0; i < *n; ++i)
      for (int64_t j = 0; j < *n; ++j)
        r.elems.push_back(i == j ? c.one() : c.zero());
    return r;
  }
  if (name == "diagonal") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    int64_t n = static_cast<int64_t>(args[0].elems.size());
    if (args[0].shape.size() != 1 || n > 4096) {
      report(DiagId::ErrExpectedScalar, where, {"argument of 'diagonal'", describeShape(args[0].shape)});
      return std::nullopt;
    }
    Value r;
    r.shape = {n, n};
    for (int64_t i = 0; i < n; ++i)
      for (int64_t j = 0; j < n; ++j)
        r.elems.push_back(i == j ? args[0].elems[i] : c.zero());
    return r;
  }
  if (name == "linspace") {
    if (!argCount(3, 3) || !lowerArgs())
      return std::nullopt;
    std::optional<int64_t> n = intArg(2);
    if (!n || *n < 2 || *n > kMaxArrayElements)
      return std::nullopt;
    Value r;
    r.shape = {*n};
    ir::ExprRef a = args[0].scalarExpr(), b = args[1].scalarExpr();
    for (int64_t i = 0; i < *n; ++i)
      r.elems.push_back(c.add(a, c.mul(c.constant(double(i) / double(*n - 1)), c.sub(b, a))));
    return r;
  }
  if (name == "transpose") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    const Value &a = args[0];
    if (a.shape.size() != 2) {
      report(DiagId::ErrExpectedScalar, where, {"argument of 'transpose'", describeShape(a.shape)});
      return std::nullopt;
    }
    Value r;
    r.shape = {a.shape[1], a.shape[0]};
    for (int64_t j = 0; j < a.shape[1]; ++j)
      for (int64_t i = 0; i < a.shape[0]; ++i)
        r.elems.push_back(a.elems[i * a.shape[1] + j]);
    return r;
  }
  if (name == "vector" || name == "scalar") {
    if (!argCount(1, 1) || !lowerArgs())
      return std::nullopt;
    Value r = args[0];
    if (name == "scalar") {
      if (r.elems.size() != 1) {
        report(DiagId::ErrExpectedScalar, where, {"argument of 'scalar'", describeShape(r.shape)});
        return std::nullopt;
      }
      return Value::scalar(r.elems[0]);
    }
    r.shape = {static_cast<int64_t>(r.elems.size())};
    return r;
  }
  if (name == "cross") {
    if (!argCount(2, 2) || !lowerArgs())
      return std::nullopt;
    if (args[0].shape != std::vector<int64_t>{3} || args[1].shape != std::vector<int64_t>{3}) {
      report(DiagId::ErrShapeMismatch, where,
             {"cross", describeShape(args[0].shape), describeShape(args[1].shape)});
      return std::nullopt;
    }
    const auto &x = args[0].elems, &y = args[1].elems;
    Value r;
    r.shape = {3};
    r.elems = {c.sub(c.mul(x[1], y[2]), c.mul(x[2], y[1])),
               c.sub(c.mul(x[2], y[0]), c.mul(x[0], y[2])),
               c.sub(c.mul(x[0], y[1]), c.mul(x[1], y[0]))};
    return r;
  }
  if (name == "reinit" || name == "assert" || name == "terminate") {
    report(DiagId::ErrMisplaced, where, {name, "an equation section"});
    return std::nullopt;
  }
  report(DiagId::ErrUnsupportedFunction, where, {name});
  return std::nullopt;
}

Value Flattener::map1Value(const Value &a,
                           const std::function<ir::ExprRef(ir::ExprRef)> &f) {
  Value r;
  r.shape = a.shape;
  for (ir::ExprRef e : a.elems)
    r.elems.push_back(f(e));
  return r;
}

std::optional<Value> Flattener::map2Value(
    const Value &a, const Value &b,
    const std::function<ir::ExprRef(ir::ExprRef, ir::ExprRef)> &f,
    const ast::Expr &where, const char *op) {
  Value r;
  if (a.shape.empty() || b.shape.empty() || a.shape == b.shape) {
    r.shape = a.shape.empty() ? b.shape : a.shape;
    size_t n = !a.shape.empty() ? a.elems.size()
               : !b.shape.empty() ? b.elems.size()
                                  : 1;
    for (size_t i = 0; i < n; ++i)
      r.elems.push_back(f(a.elems[a.shape.empty() ? 0 : i],
                          b.elems[b.shape.empty() ? 0 : i]));
    return r;
  }
  report(DiagId::ErrShapeMismatch, SourceRange{where.loc, where.length},
         {op, describeShape(a.shape), describeShape(b.shape)});
  return std::nullopt;
}

} // namespace ldae::frontend
