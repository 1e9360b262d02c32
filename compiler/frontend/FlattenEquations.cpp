// Equations of the instance tree -> scalar residuals: array equations
// element by element, for-equations unrolled, if-equations decided at
// compile time when their conditions are parameter expressions (else each
// equation becomes an if-expression residual, branches of equal size),
// when-equations kept as ir::WhenClause, declaration bindings as equations.
// Every equation keeps its location, component path and text.
#include "frontend/Flattener.h"

namespace ldae::frontend {

void Flattener::addEquation(EqSink &sink, ir::ExprRef lhs, ir::ExprRef rhs,
                            const ast::Equation &eq, const Scope &scope) {
  ir::Equation e;
  e.residual = ctx().sub(lhs, rhs);
  e.loc = eq.loc;
  e.component = scope.inst ? scope.inst->path : "";
  e.origin = sink.origin;
  e.text = eq.text;
  if (!sink.when) {
    sink.out->push_back(std::move(e));
    return;
  }
  // In a when-clause an equation assigns its left side.
  if (lhs->kind() != ir::ExprKind::Variable || lhs->order() != 0) {
    report(DiagId::ErrWhenTarget, SourceRange{eq.loc, eq.length}, {});
    return;
  }
  sink.when->equations.push_back(std::move(e));
  sink.when->targets.push_back(lhs);
}

void Flattener::flattenInstance(InstNode &node) {
  // An `outer` component's variables and equations are its inner's.
  if (node.state != InstNode::State::Done || node.inner || overBudget())
    return;
  InstanceContext context(*this, &node);
  if (node.isLeaf()) {
    if (node.binding)
      flattenBinding(node);
    return;
  }
  if (node.isArray()) {
    for (auto &e : node.elements)
      flattenInstance(*e);
    return;
  }
  for (auto &m : node.members) {
    flattenInstance(*m);
    if (m->innerHalf)
      flattenInstance(*m->innerHalf);
  }
  for (const auto &[eq, cls] : node.equations) {
    EqSink sink;
    sink.out = &model_->equations;
    flattenEquation(*eq, Scope{&node, cls}, nullptr, sink);
  }
  for (const auto &[section, cls] : node.algorithms)
    flattenAlgorithm(*section, Scope{&node, cls});
  for (const auto &[section, cls] : node.initialAlgorithms)
    flattenAlgorithm(*section, Scope{&node, cls}, /*initial=*/true);
  for (const auto &[eq, cls] : node.initialEquations) {
    if (adoptedInitialEquations_.count({&node, eq}))
      continue;
    EqSink sink;
    sink.out = &model_->initialEquations;
    sink.origin = ir::EquationOrigin::Initial;
    flattenEquation(*eq, Scope{&node, cls}, nullptr, sink);
  }
}

void Flattener::flattenBinding(InstNode &leaf) {
  const Mod &b = *leaf.binding;
  std::optional<Value> v = lowerModValue(b);
  if (!v)
    return;
  SourceRange where{b.loc, b.length};
  if (v->isString) {
    report(DiagId::ErrModifierType, where,
           {"binding of '" + leaf.path + "'", "a number", "a string"});
    return;
  }
  if (!v->shape.empty() && v->shape != leaf.dims) {
    report(DiagId::ErrEquationShape, where,
           {describeShape(leaf.dims), describeShape(v->shape)});
    return;
  }
  for (size_t i = 0; i < leaf.slots.size(); ++i) {
    ir::Equation e;
    ir::ExprRef value = v->shape.empty() ? v->elems[0] : v->elems[i];
    e.residual = ctx().sub(ctx().var(leaf.slots[i].id), value);
    e.loc = b.loc;
    e.component = leaf.parent ? leaf.parent->path : "";
    e.origin = leaf.initialParameter ? ir::EquationOrigin::Initial
                                     : ir::EquationOrigin::Binding;
    e.text = b.text.empty() ? leaf.decl->text : b.text;
    (leaf.initialParameter ? model_->initialEquations : model_->equations)
        .push_back(std::move(e));
  }
}

void Flattener::flattenEquation(const ast::Equation &eq, const Scope &scope,
                                Env *env, EqSink &sink) {
  if (overBudget())
    return;
  SourceRange where{eq.loc, eq.length};
  if (connectSweep_ && !containsConnect(eq))
    return;
  switch (eq.kind) {
  case ast::EquationKind::Simple: {
    if (eq.lhs->kind == ast::ExprKind::Tuple) {
      // (a, b) = f(x): one equation per named output.
      if (eq.rhs->kind != ast::ExprKind::Call) {
        report(DiagId::ErrMisplaced, where, {"(a, b)", "the left side of a call"});
        return;
      }
      auto outs = lowerCallOutputs(*eq.rhs, scope, env);
      if (!outs)
        return;
      if (eq.lhs->ops.size() > outs->size()) {
        report(DiagId::ErrTooManyTargets, where,
               {std::to_string(eq.lhs->ops.size()), std::to_string(outs->size())});
        return;
      }
      for (size_t k = 0; k < eq.lhs->ops.size(); ++k) {
        if (!eq.lhs->ops[k])
          continue;
        std::optional<Value> l = lower(*eq.lhs->ops[k], scope, env);
        if (!l)
          return;
        const Value &r = (*outs)[k];
        if (l->shape != r.shape || l->isString) {
          report(DiagId::ErrEquationShape, where,
                 {describeShape(l->shape), describeShape(r.shape)});
          return;
        }
        for (size_t i = 0; i < l->elems.size(); ++i)
          addEquation(sink, l->elems[i], r.elems[i], eq, scope);
      }
      return;
    }
    std::optional<Value> l = lower(*eq.lhs, scope, env);
    std::optional<Value> r = lower(*eq.rhs, scope, env);
    if (!l || !r)
      return;
    if (l->isString || r->isString) {
      report(DiagId::ErrStringOperand, where, {"="});
      return;
    }
    if (l->shape != r->shape) {
      report(DiagId::ErrEquationShape, where,
             {describeShape(l->shape), describeShape(r->shape)});
      return;
    }
    for (size_t i = 0; i < l->elems.size(); ++i)
      addEquation(sink, l->elems[i], r->elems[i], eq, scope);
    return;
  }
  case ast::EquationKind::For: {
    Env local{env, {}};
    std::function<void(size_t)> loop = [&](size_t k) {
      if (k == eq.iterators.size()) {
        for (const ast::Equation &body : eq.branches[0])
          flattenEquation(body, scope, &local, sink);
        return;
      }
      auto values = iteratorValues(eq.iterators[k], scope, &local);
      if (!values)
        return;
      for (double x : *values) {
        local.set(eq.iterators[k].name, Value::scalar(ctx().constant(x)));
        loop(k + 1);
        if (overBudget())
          return;
      }
    };
    loop(0);
    return;
  }
  case ast::EquationKind::Connect:
    if (connectsCollected_)
      return; // in before every other equation (collectConnects)
    if (sink.when || sink.inVariableIf ||
        sink.origin == ir::EquationOrigin::Initial) {
      report(DiagId::ErrMisplaced, where,
             {"connect", "equations outside when, initial and variable if"});
      return;
    }
    addConnect(eq, scope, env);
    return;
  case ast::EquationKind::If:
    flattenIf(eq, scope, env, sink);
    return;
  case ast::EquationKind::When:
    flattenWhen(eq, scope, env, sink);
    return;
  case ast::EquationKind::Call:
    flattenCallEquation(eq, scope, env, sink);
    return;
  }
}

void Flattener::flattenIf(const ast::Equation &eq, const Scope &scope,
                          Env *env, EqSink &sink) {
  // Conditions known at compile time pick their branch; the first
  // condition on variables switches to residual merging.
  std::vector<ir::ExprRef> conds; // null: the else branch
  std::vector<const std::vector<ast::Equation> *> branches;
  for (size_t k = 0; k < eq.conds.size(); ++k) {
    const ast::Expr &ce = *eq.conds[k];
    std::optional<Value> c = lower(ce, scope, env);
    if (!c)
      return;
    if (!c->isScalar()) {
      report(DiagId::ErrExpectedScalar, SourceRange{ce.loc, ce.length},
             {"condition", describeShape(c->shape)});
      return;
    }
    std::optional<double> known = constantValue(c->scalarExpr());
    if (known && *known == 0)
      continue;
    if (known) {
      conds.push_back(nullptr);
      branches.push_back(&eq.branches[k]);
      break;
    }
    conds.push_back(c->scalarExpr());
    branches.push_back(&eq.branches[k]);
  }
  if (conds.empty() || conds.back() != nullptr) {
    static const std::vector<ast::Equation> none;
    conds.push_back(nullptr);
    branches.push_back(eq.branches.size() > eq.conds.size() ? &eq.branches.back()
                                                            : &none);
  }
  if (conds.size() == 1) {
    for (const ast::Equation &body : *branches[0])
      flattenEquation(body, scope, env, sink);
    return;
  }
  // A connect under a condition on variables is an error the main sweep
  // reports.
  if (connectSweep_)
    return;
  if (sink.when) {
    flattenIfInWhen(eq, conds, branches, scope, env, sink);
    return;
  }
  // Flatten every branch separately, then merge residual by residual.
  std::vector<std::vector<ir::Equation>> results(branches.size());
  ir::ExprRef noEarlierBranch = sink.branchTaken;
  for (size_t k = 0; k < branches.size(); ++k) {
    EqSink sub = sink;
    sub.out = &results[k];
    sub.inVariableIf = true;
    sub.branchTaken = !conds[k] ? noEarlierBranch
                      : noEarlierBranch
                          ? ctx().logicalAnd(noEarlierBranch, conds[k])
                          : conds[k];
    if (conds[k])
      noEarlierBranch = noEarlierBranch
                            ? ctx().logicalAnd(noEarlierBranch,
                                               ctx().logicalNot(conds[k]))
                            : ctx().logicalNot(conds[k]);
    for (const ast::Equation &body : *branches[k])
      flattenEquation(body, scope, env, sub);
  }
  for (size_t k = 1; k < results.size(); ++k)
    if (results[k].size() != results[0].size()) {
      report(DiagId::ErrIfBranchCount, SourceRange{eq.loc, 2},
             {std::to_string(results[0].size()), std::to_string(results[k].size())});
      return;
    }
  for (size_t i = 0; i < results[0].size(); ++i) {
    ir::ExprRef r = results.back()[i].residual;
    for (size_t k = results.size() - 1; k-- > 0;)
      r = ctx().ifThenElse(conds[k], results[k][i].residual, r);
    ir::Equation e = results[0][i];
    e.residual = r;
    e.text = eq.text;
    e.loc = eq.loc;
    sink.out->push_back(std::move(e));
  }
}

void Flattener::flattenIfInWhen(
    const ast::Equation &eq, const std::vector<ir::ExprRef> &conds,
    const std::vector<const std::vector<ast::Equation> *> &branches,
    const Scope &scope, Env *env, EqSink &sink) {
  // Each branch assigns the same variables (MLS 8.3.4; MSL's SignalExtrema
  // in another order per branch): `v = if c1 then e1 elseif ... else en`.
  std::vector<ir::WhenClause> parts(branches.size());
  for (size_t k = 0; k < branches.size(); ++k) {
    EqSink sub = sink;
    sub.when = &parts[k];
    for (const ast::Equation &body : *branches[k])
      flattenEquation(body, scope, env, sub);
    if (!parts[k].reinits.empty() || !parts[k].terminates.empty() ||
        !parts[k].asserts.empty()) {
      report(DiagId::ErrUnsupported, eq.loc,
             {"reinit, terminate or assert in an if-equation on variables "
              "inside a when-equation"});
      return;
    }
  }
  auto valueIn = [&](const ir::WhenClause &part, ir::ExprRef target)
      -> ir::ExprRef {
    for (size_t i = 0; i < part.targets.size(); ++i)
      if (part.targets[i] == target) // residual: target - value
        return ctx().sub(target, part.equations[i].residual);
    return nullptr;
  };
  const ir::WhenClause &first = parts[0];
  for (size_t k = 1; k < parts.size(); ++k)
    if (parts[k].targets.size() != first.targets.size()) {
      report(DiagId::ErrIfBranchCount, SourceRange{eq.loc, 2},
             {std::to_string(first.targets.size()),
              std::to_string(parts[k].targets.size())});
      return;
    }
  for (size_t i = 0; i < first.targets.size(); ++i) {
    ir::ExprRef target = first.targets[i];
    ir::ExprRef value = valueIn(parts.back(), target);
    for (size_t k = parts.size() - 1; value && k-- > 0;) {
      ir::ExprRef branch = valueIn(parts[k], target);
      value = branch ? ctx().ifThenElse(conds[k], branch, value) : nullptr;
    }
    if (!value) {
      report(DiagId::ErrUnsupported, eq.loc,
             {"branches of an if-equation inside a when-equation that assign "
              "different variables ('" +
              model_->variables[target->var()].name + "')"});
      return;
    }
    ir::Equation e = first.equations[i];
    e.residual = ctx().sub(target, value);
    e.text = eq.text;
    e.loc = eq.loc;
    sink.when->equations.push_back(std::move(e));
    sink.when->targets.push_back(target);
  }
}

void Flattener::flattenWhen(const ast::Equation &eq, const Scope &scope,
                            Env *env, EqSink &sink) {
  SourceRange where{eq.loc, 4};
  if (sink.when || sink.inVariableIf ||
      sink.origin == ir::EquationOrigin::Initial) {
    report(DiagId::ErrMisplaced, where,
           {"when", "equations outside when, initial and variable if"});
    return;
  }
  // `elsewhen c2` fires when c2 does and no earlier branch fires (the
  // events pass gives the branches their priority).
  for (size_t k = 0; k < eq.conds.size(); ++k) {
    const ast::Expr &ce = *eq.conds[k];
    std::optional<Value> c = lower(ce, scope, env);
    if (!c)
      return;
    if (c->isString || c->elems.empty()) {
      report(DiagId::ErrExpectedScalar, SourceRange{ce.loc, ce.length},
             {"when-condition", "a string"});
      return;
    }
    // A vector of conditions fires when any element becomes true.
    ir::ExprRef cond = ctx().logicalOr(c->elems);
    ir::WhenClause clause;
    clause.condition = cond;
    clause.elements = c->elems;
    clause.elsewhen = k > 0;
    clause.loc = k == 0 ? eq.loc : ce.loc;
    EqSink body;
    body.when = &clause;
    std::optional<ImpureContext> atStart;
    std::optional<FiringContext> firing;
    if (isInitialCall(ce))
      atStart.emplace(*this);
    else
      firing.emplace(*this);
    {
      WhenAssertsScope checkedWhereItFires(*this, &clause.asserts);
      for (const ast::Equation &b : eq.branches[k])
        flattenEquation(b, scope, env, body);
    }
    if (firing)
      keepImpureCalls(clause);
    model_->whenClauses.push_back(std::move(clause));
  }
}

void Flattener::flattenCallEquation(const ast::Equation &eq, const Scope &scope,
                                    Env *env, EqSink &sink) {
  const ast::Expr &call = *eq.lhs;
  SourceRange where{eq.loc, eq.length};
  const std::string &name = call.text;
  if (name == "assert") {
    flattenAssert(eq, scope, env, sink);
    return;
  }
  if (name == "terminate") {
    if (!sink.when) {
      report(DiagId::ErrMisplaced, where, {"terminate", "a when-equation"});
      return;
    }
    if (call.args.size() != 1 || !call.args[0].name.empty()) {
      report(DiagId::ErrCallArgCount, where,
             {"terminate", "1", std::to_string(call.args.size())});
      return;
    }
    const ast::Expr &msg = *call.args[0].value;
    std::optional<std::string> text = messageText(msg, "terminate", scope, env);
    if (!text)
      return;
    sink.when->terminates.push_back({*text, eq.loc});
    return;
  }
  if (name != "reinit") {
    report(DiagId::ErrCallAsEquation, where, {name});
    return;
  }
  if (!sink.when) {
    report(DiagId::ErrMisplaced, where, {"reinit", "a when-equation"});
    return;
  }
  if (call.args.size() != 2 || !call.args[0].name.empty()) {
    report(DiagId::ErrCallArgCount, where,
           {"reinit", "2", std::to_string(call.args.size())});
    return;
  }
  std::optional<Value> target = lower(*call.args[0].value, scope, env);
  std::optional<Value> value = lower(*call.args[1].value, scope, env);
  if (!target || !value)
    return;
  if (target->isString || value->isString ||
      (!value->shape.empty() && value->shape != target->shape)) {
    report(DiagId::ErrEquationShape, where,
           {describeShape(target->shape), describeShape(value->shape)});
    return;
  }
  for (size_t i = 0; i < target->elems.size(); ++i) {
    ir::ExprRef t = target->elems[i];
    if (t->kind() != ir::ExprKind::Variable || t->order() != 0) {
      report(DiagId::ErrReinitTarget, SourceRange{call.args[0].value->loc,
                                                  call.args[0].value->length},
             {});
      return;
    }
    ir::Reinit r;
    r.var = t->var();
    r.value = value->shape.empty() ? value->elems[0] : value->elems[i];
    r.loc = eq.loc;
    sink.when->reinits.push_back(r);
  }
}

void Flattener::flattenAssert(const ast::Equation &eq, const Scope &scope,
                              Env *env, EqSink &sink) {
  const ast::Expr &call = *eq.lhs;
  SourceRange where{eq.loc, eq.length};
  const ast::Expr *cond = nullptr, *message = nullptr, *level = nullptr;
  for (size_t i = 0; i < call.args.size(); ++i) {
    const ast::Arg &a = call.args[i];
    if (a.name == "condition" || (a.name.empty() && i == 0))
      cond = a.value.get();
    else if (a.name == "message" || (a.name.empty() && i == 1))
      message = a.value.get();
    else if (a.name == "level" || (a.name.empty() && i == 2))
      level = a.value.get();
  }
  if (!cond || !message || call.args.size() > 3) {
    report(DiagId::ErrCallArgCount, where,
           {"assert", "2 to 3", std::to_string(call.args.size())});
    return;
  }
  ir::Assert a;
  messageValues_ = &a.messageValues;
  std::optional<std::string> text = messageText(*message, "assert", scope, env);
  messageValues_ = nullptr;
  if (!text)
    return;
  a.message = *text;
  a.loc = eq.loc;
  if (level) {
    // AssertionLevel.warning (1) or .error (2), or a parameter of the type
    // (MSL's AssertCondition).
    std::optional<double> l =
        evalConstant(*level, scope, env, "level of 'assert'");
    if (!l)
      return;
    if (*l != 1 && *l != 2) {
      report(DiagId::ErrAssertLevel, SourceRange{level->loc, level->length},
             {});
      return;
    }
    a.level = *l == 1 ? 1 : 0;
  }
  std::optional<Value> c = lower(*cond, scope, env);
  if (!c)
    return;
  if (c->isString || c->elems.empty()) {
    report(DiagId::ErrExpectedScalar, SourceRange{cond->loc, cond->length},
           {"condition of 'assert'", "a string"});
    return;
  }
  // An array condition holds where every element does.
  a.condition = ctx().logicalAnd(c->elems);
  // In a branch of a variable if-equation it checks while the branch is
  // taken (LimIntegrator's check of its start, under initial()).
  if (sink.branchTaken)
    a.condition = ctx().logicalOr(ctx().logicalNot(sink.branchTaken), a.condition);
  (sink.when ? sink.when->asserts : model_->asserts).push_back(std::move(a));
}

std::optional<std::string>
Flattener::messageText(const ast::Expr &message, const char *what,
                       const Scope &scope, Env *env) {
  std::optional<Value> v = lower(message, scope, env);
  if (!v)
    return std::nullopt;
  if (!v->isString) {
    report(DiagId::ErrMessageNotLiteral,
           SourceRange{message.loc, message.length}, {what});
    return std::nullopt;
  }
  return v->str;
}

} // namespace ldae::frontend
