// User functions are inlined at their calls: the body runs symbolically
// over IR expressions. Inputs take the argument values (or their defaults),
// each assignment rebinds a local, an if-statement whose condition depends
// on variables runs both branches and merges every local with an
// if-expression, and for-loops over constant ranges unroll. The outputs'
// final expressions are the call's values.
#include "frontend/ExternalObject.h"
#include "frontend/Flattener.h"

#include <algorithm>
#include <functional>

#include <cmath>

namespace ldae::frontend {
namespace {

constexpr size_t kMaxStatements = 1'000'000; // per top-level inline
constexpr unsigned kMaxWhileIterations = 100'000;

struct InlineDepth {
  unsigned &depth;
  explicit InlineDepth(unsigned &d) : depth(++d) {}
  ~InlineDepth() { --depth; }
};

bool isInput(const ast::Component &c) {
  return c.prefix.causality == ast::Causality::Input;
}
bool isOutput(const ast::Component &c) {
  return c.prefix.causality == ast::Causality::Output;
}

} // namespace

std::optional<std::vector<Value>>
Flattener::inlineCall(const ast::ClassDef &fn, const ast::Expr &call,
                      const Scope &scope, Env *env,
                      const std::vector<CallArgument> *given) {
  SourceRange where{call.loc, call.length};
  if (inlineDepth == 0)
    statementBudget_ = 0;
  InlineDepth depth(inlineDepth);
  if (inlineDepth > kMaxInlineDepth) {
    report(DiagId::ErrInlineTooDeep, where,
           {fn.name, std::to_string(kMaxInlineDepth)});
    return std::nullopt;
  }
  // An impure function is called when compiling, where a parameter's value
  // is computed (CompileTimeCalls.cpp), or at run time in a when-clause
  // (FiringContext); elsewhere it is refused at the call the model makes.
  if (fn.impure && impureContext_ == 0 && firingContext_ == 0) {
    report(DiagId::ErrUnsupported, where,
           {"a call of impure function '" + fn.name +
            "' outside a parameter's value or a when-clause (ldaec calls "
            "impure functions when compiling, where a parameter's value is "
            "computed, and at run time where a when-clause fires)"});
    return std::nullopt;
  }
  std::optional<FunctionParts> parts = functionParts(fn, where);
  if (!parts)
    return std::nullopt;
  const std::vector<const ast::Component *> &comps = parts->comps;
  const std::vector<const ast::ClassDef *> &owner = parts->owner;
  const ast::ClassDef *body = parts->body;
  std::vector<const ast::Component *> inputs;
  std::vector<const ast::ClassDef *> inputOwner;
  for (size_t i = 0; i < comps.size(); ++i)
    if (isInput(*comps[i])) {
      inputs.push_back(comps[i]);
      inputOwner.push_back(owner[i]);
    }

  // Match the arguments to inputs: positional first, then by name.
  std::vector<const ast::Expr *> bound(inputs.size(), nullptr);
  size_t positional = 0;
  for (const ast::Arg &a : call.args) {
    if (a.name.empty()) {
      // Inputs a partial application bound take no positional argument.
      while (given && positional < inputs.size() &&
             (*given)[positional].preBound)
        ++positional;
      if (positional >= inputs.size()) {
        report(DiagId::ErrCallArgCount, where,
               {fn.name, std::to_string(inputs.size()),
                std::to_string(call.args.size())});
        return std::nullopt;
      }
      bound[positional++] = a.value.get();
      continue;
    }
    size_t k = 0;
    while (k < inputs.size() && inputs[k]->name != a.name)
      ++k;
    if (k == inputs.size()) {
      std::vector<std::string> names;
      for (const auto *in : inputs)
        names.push_back(in->name);
      std::string best = closestName(a.name, names);
      if (best.empty())
        report(DiagId::ErrNoSuchInput, SourceRange{a.value->loc, a.value->length},
               {fn.name, a.name});
      else
        report(DiagId::ErrNoSuchInputSuggest,
               SourceRange{a.value->loc, a.value->length}, {fn.name, a.name, best});
      return std::nullopt;
    }
    if (bound[k]) {
      report(DiagId::ErrArgumentTwice, SourceRange{a.value->loc, a.value->length},
             {a.name, fn.name});
      return std::nullopt;
    }
    bound[k] = a.value.get();
  }

  // The arguments' values, in the caller's scope. An argument with more
  // dimensions than its input declares makes the call vectorized (MLS
  // 12.4.6: MSL's to_deg(Phi[1:nfi]) of a scalar input).
  std::vector<CallArgument> lowered;
  if (!given) {
    lowered.resize(inputs.size());
    std::optional<std::vector<int64_t>> over; // the dimensions mapped over
    bool mismatched = false;
    for (size_t k = 0; k < inputs.size(); ++k) {
      if (!bound[k])
        continue;
      if (functionTypeOf(inputs[k]->typeName, *inputOwner[k])) {
        lowered[k].function = functionArgument(*bound[k], scope, env);
        if (!lowered[k].function)
          return std::nullopt;
        continue;
      }
      lowered[k].value = lower(*bound[k], scope, env);
      if (!lowered[k].value)
        return std::nullopt;
      const Value &v = *lowered[k].value;
      if (v.isString || v.shape.size() <= inputs[k]->dims.size())
        continue;
      std::vector<int64_t> lead(
          v.shape.begin(),
          v.shape.end() - static_cast<std::ptrdiff_t>(inputs[k]->dims.size()));
      mismatched = mismatched || (over && *over != lead);
      over = lead;
    }
    if (over && !mismatched)
      return vectorizedCall(fn, call, scope, env, inputs, lowered, *over);
    given = &lowered;
  }
  Env fenv; // a function sees its own names only, never the caller's
  // An external function also takes Strings and external objects.
  auto externalOnlyType = [&](const ast::Name &type) {
    if (!fn.isExternal)
      return false;
    if (!type.global && type.parts.size() == 1 && type.parts[0] == "String")
      return true;
    const ast::ClassDef *cls =
        classes_.resolveClass(type, &fn, fn.file, /*report=*/false);
    return cls && !cls->isShort && isExternalObject(*cls);
  };
  auto isStringType = [](const ast::Name &type) {
    return !type.global && type.parts.size() == 1 && type.parts[0] == "String";
  };
  for (size_t i = 0; i < comps.size(); ++i) {
    const ast::Component &c = *comps[i];
    // Strings are values known when compiling (Value::str): scalars only.
    bool scalarString = isStringType(c.typeName) && c.dims.empty();
    if (!isNumericType(c.typeName, *owner[i]) && !scalarString &&
        !(fn.isExternal && externalOnlyType(c.typeName)) &&
        !(isInput(c) && functionTypeOf(c.typeName, *owner[i]))) {
      report(DiagId::ErrUnsupported, c.typeName.loc,
             {"function variables of type '" + c.typeName.str() + "'"});
      return std::nullopt;
    }
  }
  size_t inputIndex = 0;
  for (size_t i = 0; i < comps.size(); ++i) {
    const ast::Component &c = *comps[i];
    Scope fscope{nullptr, owner[i]};
    std::optional<Value> value;
    if (isInput(c)) {
      const ast::Expr *arg = bound[inputIndex];
      const CallArgument &known = (*given)[inputIndex++];
      if (functionTypeOf(c.typeName, *owner[i])) {
        std::optional<FunctionValue> f = known.function;
        if (!f && arg)
          f = functionArgument(*arg, scope, env);
        if (!f) {
          if (!arg)
            report(DiagId::ErrMissingArgument, where, {c.name, fn.name});
          return std::nullopt;
        }
        fenv.functions.emplace_back(c.name, std::move(*f));
        continue;
      }
      if (arg || known.value) {
        value = known.value;
        if (!value && arg)
          value = lower(*arg, scope, env);
        if (!value)
          return std::nullopt;
        SourceRange argAt =
            arg ? SourceRange{arg->loc, arg->length} : where;
        if (value->isString != isStringType(c.typeName)) {
          report(DiagId::ErrArgumentType, argAt,
                 {c.name, fn.name, "a number", "a string"});
          return std::nullopt;
        }
        // Declared sizes: `:` takes the argument's size.
        bool ok = value->isString || value->shape.size() == c.dims.size();
        for (size_t k = 0; ok && k < c.dims.size(); ++k) {
          if (c.dims[k]->kind == ast::ExprKind::Colon)
            continue;
          std::optional<int64_t> n = evalInteger(*c.dims[k], fscope, &fenv,
                                                 "array size of '" + c.name + "'");
          if (!n)
            return std::nullopt;
          ok = *n == value->shape[k];
        }
        if (!ok) {
          std::vector<int64_t> declared;
          for (const auto &d : c.dims)
            declared.push_back(d->kind == ast::ExprKind::Colon ? 0 : -1);
          report(DiagId::ErrArgumentType, argAt,
                 {c.name, fn.name,
                  c.dims.empty() ? "a scalar"
                                 : "an array of " + std::to_string(c.dims.size()) +
                                       " dimension(s)",
                  describeShape(value->shape)});
          return std::nullopt;
        }
      } else if (c.mod && c.mod->value) {
        value = lower(*c.mod->value, fscope, &fenv);
        if (!value)
          return std::nullopt;
      } else {
        report(DiagId::ErrMissingArgument, where, {c.name, fn.name});
        return std::nullopt;
      }
    } else if (isStringType(c.typeName)) {
      // A String output or local: "" until the body assigns it.
      value = Value::string("");
      if (c.mod && c.mod->value) {
        value = lower(*c.mod->value, fscope, &fenv);
        if (!value)
          return std::nullopt;
        if (!value->isString) {
          report(DiagId::ErrModifierType, c.mod->value->loc,
                 {"the value of String '" + c.name + "'", "a string",
                  "a number"});
          return std::nullopt;
        }
      }
    } else {
      // Outputs and locals: unassigned (null) until the body assigns them.
      Value v;
      for (const auto &d : c.dims) {
        if (d->kind == ast::ExprKind::Colon) {
          report(DiagId::ErrUnsupported, d->loc,
                 {"function outputs of unknown size"});
          return std::nullopt;
        }
        std::optional<int64_t> n =
            evalInteger(*d, fscope, &fenv, "array size of '" + c.name + "'");
        if (!n || *n < 0 || *n > kMaxArrayElements)
          return std::nullopt;
        v.shape.push_back(*n);
      }
      int64_t count = 1;
      for (int64_t n : v.shape)
        count *= n;
      v.elems.assign(count, nullptr);
      if (c.mod && c.mod->value) {
        std::optional<Value> init = lower(*c.mod->value, fscope, &fenv);
        if (!init)
          return std::nullopt;
        if (init->shape != v.shape || init->isString) {
          report(DiagId::ErrShapeMismatch, c.mod->value->loc,
                 {":=", describeShape(v.shape), describeShape(init->shape)});
          return std::nullopt;
        }
        v = *init;
      }
      value = v;
    }
    fenv.set(c.name, std::move(*value));
  }
  if (fn.isExternal)
    return externalCall(fn, fenv);
  const Env atEntry = fenv; // the inputs' values, every variable's shape
  if (execStatements(body->algorithm, fn, Scope{nullptr, body}, fenv) !=
      ExecResult::Ok) {
    if (!compileInstead_)
      return std::nullopt;
    compileInstead_ = false;
    return compiledCall(fn, *parts, atEntry, where);
  }
  std::vector<Value> outputs;
  for (const ast::Component *comp : comps) {
    const ast::Component &c = *comp;
    if (!isOutput(c))
      continue;
    Value *v = fenv.find(c.name);
    for (ir::ExprRef e : v->elems)
      if (!e) {
        Diagnostic &d =
            report(DiagId::ErrOutputNotAssigned, where, {c.name, fn.name});
        DiagnosticEngine::addNote(d, c.loc, DiagId::NoteDeclaredHere, {c.name});
        return std::nullopt;
      }
    outputs.push_back(*v);
  }
  return outputs;
}

bool Flattener::assign(const ast::Expr &target, Value value,
                       const ast::ClassDef &fn, const Scope &scope, Env &env) {
  SourceRange where{target.loc, target.length};
  if (target.kind != ast::ExprKind::Ref || target.parts.size() != 1) {
    report(DiagId::ErrBadAssignTarget, where, {});
    return false;
  }
  const std::string &name = target.parts[0].name;
  Value *slot = env.find(name);
  if (!slot) {
    std::string best = suggest(name, scope, &env);
    if (best.empty())
      report(DiagId::ErrUndefinedName, where, {name});
    else
      report(DiagId::ErrUndefinedNameSuggest, where, {name, best});
    return false;
  }
  for (const ast::Component &c : fn.components)
    if (c.name == name && isInput(c)) {
      report(DiagId::ErrAssignInput, where, {name});
      return false;
    }
  // After a break or return on some paths, the assignment holds on the
  // others only.
  ir::ExprRef exited = exitedOf(env);
  if (value.isString || slot->isString) {
    // A String is one text known when compiling: a whole assignment on
    // every path.
    if (value.isString != slot->isString ||
        !target.parts[0].subscripts.empty()) {
      report(DiagId::ErrStringOperand, where, {":="});
      return false;
    }
    if (exited) {
      report(DiagId::ErrUnsupported, where,
             {"a String assigned after a break or return on some paths"});
      return false;
    }
    slot->str = std::move(value.str);
    return true;
  }
  auto write = [&](ir::ExprRef &element, ir::ExprRef v) {
    if (!exited)
      element = v;
    else
      element = element ? ctx().ifThenElse(exited, element, v) : nullptr;
  };
  const auto &subs = target.parts[0].subscripts;
  if (subs.empty()) {
    if (value.shape != slot->shape) {
      if (!value.shape.empty()) {
        report(DiagId::ErrShapeMismatch, where,
               {":=", describeShape(slot->shape), describeShape(value.shape)});
        return false;
      }
      // A scalar fills the array.
      for (ir::ExprRef &element : slot->elems)
        write(element, value.elems[0]);
      return true;
    }
    for (size_t i = 0; i < slot->elems.size(); ++i)
      write(slot->elems[i], value.elems[i]);
    return true;
  }
  std::vector<int64_t> shape, offsets;
  std::vector<int64_t> dims = slot->shape;
  std::vector<RunTimeSubscript> runTime;
  if (!applySubscripts(subs, dims, name, scope, &env, shape, offsets,
                       target.loc, &runTime))
    return false;
  slot = env.find(name); // lowering subscripts may not move it, but be safe
  if (!runTime.empty()) {
    size_t kept = offsets.size();
    for (const RunTimeSubscript &sub : runTime)
      kept = sub.size ? kept / static_cast<size_t>(sub.size) : 0;
    if (!value.shape.empty() && value.elems.size() != kept) {
      report(DiagId::ErrShapeMismatch, where,
             {":=", describeShape(shape), describeShape(value.shape)});
      return false;
    }
    assignAtRunTime(value, shape, offsets, runTime, *slot, write);
    return true;
  }
  if (!value.shape.empty() && value.elems.size() != offsets.size()) {
    report(DiagId::ErrShapeMismatch, where,
           {":=", describeShape(shape), describeShape(value.shape)});
    return false;
  }
  for (size_t i = 0; i < offsets.size(); ++i)
    write(slot->elems[offsets[i]],
          value.shape.empty() ? value.elems[0] : value.elems[i]);
  return true;
}

Flattener::ExecResult Flattener::execIf(const ast::Statement &st, size_t branch,
                                        const ast::ClassDef &fn,
                                        const Scope &fscope, Env &env) {
  if (branch == st.conds.size()) {
    if (branch < st.branches.size())
      return execStatements(st.branches[branch], fn, fscope, env);
    return ExecResult::Ok;
  }
  const ast::Expr &condExpr = *st.conds[branch];
  std::optional<Value> cond = lower(condExpr, fscope, &env);
  if (!cond)
    return ExecResult::Error;
  if (!cond->isScalar()) {
    report(DiagId::ErrExpectedScalar, SourceRange{condExpr.loc, condExpr.length},
           {"condition", describeShape(cond->shape)});
    return ExecResult::Error;
  }
  if (std::optional<double> known = constantValue(cond->scalarExpr())) {
    if (*known != 0)
      return execStatements(st.branches[branch], fn, fscope, env);
    return execIf(st, branch + 1, fn, fscope, env);
  }
  // A condition on variables: both ways, merged element by element.
  Env thenEnv = env, elseEnv = env;
  ir::ExprRef c = cond->scalarExpr();
  const ir::ExprRef outerGuard = statementGuard_;
  struct GuardRestore {
    ir::ExprRef &guard, saved;
    ~GuardRestore() { guard = saved; }
  } restore{statementGuard_, outerGuard};
  {
    std::optional<ImpureContext> atStart;
    if (isInitialCall(condExpr))
      atStart.emplace(*this);
    statementGuard_ = outerGuard ? ctx().logicalAnd(outerGuard, c) : c;
    if (execStatements(st.branches[branch], fn, fscope, thenEnv) !=
        ExecResult::Ok)
      return ExecResult::Error;
  }
  ir::ExprRef notC = ctx().logicalNot(c);
  statementGuard_ = outerGuard ? ctx().logicalAnd(outerGuard, notC) : notC;
  if (execIf(st, branch + 1, fn, fscope, elseEnv) != ExecResult::Ok)
    return ExecResult::Error;
  statementGuard_ = outerGuard;
  auto mergeExit = [&](ir::ExprRef a, ir::ExprRef b) -> ir::ExprRef {
    if (a == b)
      return a;
    return ctx().ifThenElse(c, a ? a : ctx().zero(), b ? b : ctx().zero());
  };
  env.breaking = mergeExit(thenEnv.breaking, elseEnv.breaking);
  env.returning = mergeExit(thenEnv.returning, elseEnv.returning);
  for (size_t k = 0; k < env.vars.size(); ++k) {
    Value &out = env.vars[k].second;
    const Value &a = thenEnv.vars[k].second, &b = elseEnv.vars[k].second;
    if (a.isString && a.str != b.str) {
      report(DiagId::ErrUnsupported, SourceRange{condExpr.loc, condExpr.length},
             {"a String '" + env.vars[k].first +
              "' that this condition, known only at run time, chooses"});
      return ExecResult::Error;
    }
    for (size_t i = 0; i < out.elems.size(); ++i) {
      ir::ExprRef x = a.elems[i], y = b.elems[i];
      out.elems[i] = x == y ? x : (x && y ? ctx().ifThenElse(c, x, y) : nullptr);
    }
  }
  return ExecResult::Ok;
}

Flattener::ExecResult
Flattener::execStatements(const std::vector<ast::Statement> &list,
                          const ast::ClassDef &fn, const Scope &fscope,
                          Env &env) {
  for (const ast::Statement &st : list) {
    if (ir::ExprRef exited = exitedOf(env))
      if (constantValue(exited).value_or(0) != 0)
        return ExecResult::Ok; // every path has left
    if (++statementBudget_ > kMaxStatements) {
      if (!fscope.inst) {
        compileInstead_ = true; // it runs as a compiled function
        return ExecResult::Error;
      }
      report(DiagId::ErrLoopTooLong, st.loc, {fn.name});
      return ExecResult::Error;
    }
    SourceRange where{st.loc, st.length};
    switch (st.kind) {
    case ast::StatementKind::Assign: {
      std::optional<Value> v = lower(*st.rhs, fscope, &env);
      if (!v || !assign(*st.lhs, std::move(*v), fn, fscope, env))
        return ExecResult::Error;
      break;
    }
    case ast::StatementKind::TupleAssign: {
      auto outs = lowerCallOutputs(*st.rhs, fscope, &env);
      if (!outs)
        return ExecResult::Error;
      if (st.targets.size() > outs->size()) {
        report(DiagId::ErrTooManyTargets, where,
               {std::to_string(st.targets.size()), std::to_string(outs->size())});
        return ExecResult::Error;
      }
      for (size_t k = 0; k < st.targets.size(); ++k)
        if (st.targets[k] &&
            !assign(*st.targets[k], (*outs)[k], fn, fscope, env))
          return ExecResult::Error;
      break;
    }
    case ast::StatementKind::Call:
      if (st.rhs->text == "assert")
        break; // checks at run time are not modelled; the model is unchanged
      // A pure function called for no result (MSL's isValidTable) changes
      // nothing but what its asserts check; it is inlined all the same,
      // so that a call of an unknown or impure function is refused.
      if (!lowerCallOutputs(*st.rhs, fscope, &env))
        return ExecResult::Error;
      break;
    case ast::StatementKind::If:
      if (execIf(st, 0, fn, fscope, env) != ExecResult::Ok)
        return ExecResult::Error;
      break;
    case ast::StatementKind::For: {
      ir::ExprRef outerBreak = env.breaking;
      env.breaking = nullptr;
      ++loopDepth_;
      bool stop = false; // every path has left the loop
      std::function<bool(size_t)> loop = [&](size_t k) -> bool {
        if (k == st.iterators.size()) {
          if (execStatements(st.branches[0], fn, fscope, env) !=
              ExecResult::Ok)
            return false;
          stop = !continueLoop(env);
          return true;
        }
        auto values = iteratorValues(st.iterators[k], fscope, &env);
        if (!values)
          return false;
        for (double x : *values) {
          if (stop)
            break;
          env.set(st.iterators[k].name, Value::scalar(ctx().constant(x)));
          if (!loop(k + 1))
            return false;
        }
        return true;
      };
      bool ok = loop(0);
      --loopDepth_;
      env.breaking = outerBreak;
      if (!ok)
        return ExecResult::Error;
      break;
    }
    case ast::StatementKind::While: {
      for (unsigned iter = 0;; ++iter) {
        if (iter > kMaxWhileIterations) {
          if (!fscope.inst) {
            compileInstead_ = true;
            return ExecResult::Error;
          }
          report(DiagId::ErrLoopTooLong, where, {fn.name});
          return ExecResult::Error;
        }
        std::optional<Value> cond = lower(*st.conds[0], fscope, &env);
        if (!cond)
          return ExecResult::Error;
        std::optional<double> known =
            cond->isScalar() ? constantValue(cond->scalarExpr()) : std::nullopt;
        if (!known && !fscope.inst) {
          // The loop runs at run time: the function is compiled
          // (CompiledFunctions.cpp).
          compileInstead_ = true;
          return ExecResult::Error;
        }
        if (!known) {
          report(DiagId::ErrNotParameterExpr,
                 SourceRange{st.conds[0]->loc, st.conds[0]->length},
                 {"a while-condition"});
          return ExecResult::Error;
        }
        if (*known == 0)
          break;
        ir::ExprRef outerBreak = env.breaking;
        env.breaking = nullptr;
        ++loopDepth_;
        bool ok = execStatements(st.branches[0], fn, fscope, env) ==
                  ExecResult::Ok;
        --loopDepth_;
        bool more = ok && continueLoop(env);
        env.breaking = outerBreak;
        if (!ok)
          return ExecResult::Error;
        if (!more)
          break;
      }
      break;
    }
    case ast::StatementKind::When:
      if (fscope.inst && algorithmWhenTargets_) {
        if (execWhenStatement(st, fn, fscope, env) != ExecResult::Ok)
          return ExecResult::Error;
        break;
      }
      report(DiagId::ErrMisplaced, where,
             {"when", fscope.inst ? "a model's equations and the top level "
                                    "of its algorithm sections"
                                  : "a model's equations"});
      return ExecResult::Error;
    case ast::StatementKind::Break:
      if (loopDepth_ == 0) {
        report(DiagId::ErrMisplaced, where, {"break", "a for or while loop"});
        return ExecResult::Error;
      }
      env.breaking = ctx().one();
      break;
    case ast::StatementKind::Return:
      if (fscope.inst) {
        report(DiagId::ErrMisplaced, where, {"return", "a function"});
        return ExecResult::Error;
      }
      env.returning = ctx().one();
      break;
    }
  }
  return ExecResult::Ok;
}

ir::ExprRef Flattener::exitedOf(const Env &env) {
  if (env.breaking && env.returning)
    return ctx().logicalOr(env.breaking, env.returning);
  return env.breaking ? env.breaking : env.returning;
}

bool Flattener::continueLoop(Env &env) {
  ir::ExprRef exited = exitedOf(env);
  return !exited || constantValue(exited).value_or(0) == 0;
}

std::optional<Flattener::FunctionParts>
Flattener::functionParts(const ast::ClassDef &fn, SourceRange where) {
  // `extends` (MSL's densities extend partialDensity, which declares the
  // input u and the output y): the variables of the bases come first, in
  // order, then the function's own; the algorithm is the one of the chain
  // that has one (MLS 12.2: at most one, possibly inherited). Each
  // variable's type and default are read in the class that declares it.
  FunctionParts parts;
  bool inherited = false;
  std::function<bool(const ast::ClassDef &, unsigned)> collect =
      [&](const ast::ClassDef &c, unsigned depth) {
        for (const ast::Extends &ext : c.extends) {
          const ast::ClassDef *base = classes_.resolveClass(
              ext.base, c.parent, c.file, /*report=*/false);
          if (!base || depth > 32 || (ext.mod && !ext.mod->args.empty())) {
            report(DiagId::ErrUnsupported, ext.loc,
                   {base ? "'extends' with modifiers in functions"
                         : "'extends' of this class in functions"});
            return false;
          }
          if (!collect(*base, depth + 1))
            return false;
        }
        for (const ast::Component &comp : c.components) {
          parts.comps.push_back(&comp);
          parts.owner.push_back(&c);
          inherited = inherited || &c != &fn;
        }
        if (!c.algorithm.empty() || c.isExternal) {
          if (parts.body) {
            report(DiagId::ErrUnsupported, c.loc,
                   {"a function with two algorithm sections"});
            return false;
          }
          parts.body = &c;
        }
        return true;
      };
  if (!collect(fn, 0))
    return std::nullopt;
  if (!parts.body)
    parts.body = &fn;
  if (parts.body->isExternal && (inherited || parts.body != &fn)) {
    report(DiagId::ErrUnsupported, where,
           {"an external function '" + fn.name + "' that inherits"});
    return std::nullopt;
  }
  return parts;
}

std::optional<std::vector<Value>> Flattener::vectorizedCall(
    const ast::ClassDef &fn, const ast::Expr &call, const Scope &scope,
    Env *env, const std::vector<const ast::Component *> &inputs,
    const std::vector<CallArgument> &args,
    const std::vector<int64_t> &over) {
  int64_t count = 1;
  for (int64_t d : over)
    count *= d;
  std::vector<Value> results;
  for (int64_t i = 0; i < count; ++i) {
    // Element i of each mapped argument, the others whole.
    std::vector<CallArgument> one(args.size());
    for (size_t k = 0; k < args.size(); ++k) {
      if (!args[k].value) {
        one[k] = args[k];
        continue;
      }
      const Value &v = *args[k].value;
      if (v.isString || v.shape.size() <= inputs[k]->dims.size()) {
        one[k] = args[k];
        continue;
      }
      Value e;
      e.shape.assign(v.shape.begin() + static_cast<std::ptrdiff_t>(over.size()),
                     v.shape.end());
      size_t n = v.elems.size() / static_cast<size_t>(count);
      e.elems.assign(v.elems.begin() + static_cast<std::ptrdiff_t>(i * n),
                     v.elems.begin() + static_cast<std::ptrdiff_t>((i + 1) * n));
      one[k].value = std::move(e);
    }
    std::optional<std::vector<Value>> outs =
        inlineCall(fn, call, scope, env, &one);
    if (!outs)
      return std::nullopt;
    if (results.empty())
      for (const Value &o : *outs) {
        Value r;
        r.shape = over;
        r.shape.insert(r.shape.end(), o.shape.begin(), o.shape.end());
        results.push_back(std::move(r));
      }
    for (size_t j = 0; j < outs->size() && j < results.size(); ++j) {
      if ((*outs)[j].isString) {
        report(DiagId::ErrUnsupported, SourceRange{call.loc, call.length},
               {"a vectorized call of a function with String outputs"});
        return std::nullopt;
      }
      results[j].elems.insert(results[j].elems.end(), (*outs)[j].elems.begin(),
                              (*outs)[j].elems.end());
    }
  }
  return results;
}

const ast::ClassDef *Flattener::functionTypeOf(const ast::Name &type,
                                               const ast::ClassDef &in) {
  if (!type.global && type.parts.size() == 1 &&
      (type.parts[0] == "Real" || type.parts[0] == "Integer" ||
       type.parts[0] == "Boolean" || type.parts[0] == "String"))
    return nullptr;
  const ast::ClassDef *cls =
      classes_.resolveClass(type, &in, in.file, /*report=*/false);
  return cls && cls->kind == ast::ClassKind::Function ? cls : nullptr;
}

std::optional<FunctionValue>
Flattener::functionArgument(const ast::Expr &e, const Scope &scope, Env *env) {
  SourceRange at{e.loc, e.length};
  if (e.kind == ast::ExprKind::Ref && e.parts.size() == 1 &&
      e.parts[0].subscripts.empty() && env)
    if (const FunctionValue *f = env->findFunction(e.parts[0].name))
      return *f;
  bool named = e.kind == ast::ExprKind::Ref ||
               (e.kind == ast::ExprKind::Call && e.partialApplication);
  if (!named) {
    report(DiagId::ErrUnsupported, at,
           {"this argument for an input of a function type (a function's "
            "name or `function f(a = ...)` is)"});
    return std::nullopt;
  }
  ast::Name fname = e.kind == ast::ExprKind::Call ? e.calleeName() : ast::Name{};
  if (e.kind == ast::ExprKind::Ref) {
    fname.global = e.global;
    for (const ast::RefPart &p : e.parts)
      fname.parts.push_back(p.name);
    fname.loc = e.loc;
    fname.length = e.length;
  }
  uint32_t file = scope.cls ? scope.cls->file : e.loc.file;
  const ast::ClassDef *fn =
      classes_.resolveClass(fname, e.global ? nullptr : scope.cls, file);
  for (unsigned guard = 0; fn && fn->isShort && guard < 16; ++guard)
    fn = classes_.resolveClass(fn->shortBase, fn->parent, fn->file);
  if (!fn)
    return std::nullopt;
  if (fn->kind != ast::ClassKind::Function) {
    report(DiagId::ErrNotAFunction, SourceRange{fname.loc, fname.length},
           {fname.str(), ast::classKindName(fn->kind)});
    return std::nullopt;
  }
  std::optional<FunctionParts> parts = functionParts(*fn, at);
  if (!parts)
    return std::nullopt;
  FunctionValue f;
  f.fn = fn;
  for (const ast::Arg &a : e.args) {
    bool input = std::any_of(
        parts->comps.begin(), parts->comps.end(),
        [&](const ast::Component *c) { return isInput(*c) && c->name == a.name; });
    if (!input) {
      report(DiagId::ErrNoSuchInput, SourceRange{a.value->loc, a.value->length},
             {fn->name, a.name});
      return std::nullopt;
    }
    std::optional<Value> v = lower(*a.value, scope, env);
    if (!v)
      return std::nullopt;
    f.bound.emplace_back(a.name, std::move(*v));
  }
  return f;
}

bool Flattener::isNumericType(const ast::Name &type, const ast::ClassDef &in) {
  // Real, Integer, Boolean, or a type that names one (MSL's `input
  // SI.Temperature T`) or an enumeration, through short classes.
  ast::Name cur = type;
  const ast::ClassDef *scope = &in;
  uint32_t file = in.file;
  for (unsigned guard = 0; guard < 32; ++guard) {
    if (!cur.global && cur.parts.size() == 1 &&
        (cur.parts[0] == "Real" || cur.parts[0] == "Integer" ||
         cur.parts[0] == "Boolean"))
      return true;
    const ast::ClassDef *cls =
        classes_.resolveClass(cur, scope, file, /*report=*/false);
    if (!cls)
      return false;
    if (enumerationOf(cls))
      return true;
    if (!cls->isShort)
      return false;
    scope = cls->parent;
    file = cls->file;
    cur = cls->shortBase;
  }
  return false;
}

} // namespace ldae::frontend
