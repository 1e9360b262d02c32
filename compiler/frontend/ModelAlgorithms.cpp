// A model's algorithm sections (MLS 11.1): each is run once symbolically,
// as a function body is (Inline.cpp), with the variables it assigns as
// locals; each assigned variable then gets one equation, `v = its value at
// the end of the section`, so that the section is as many equations as it
// assigns variables. A discrete variable starts from pre(v) (a branch that
// does not assign it keeps it); a continuous one must be assigned on every
// path before it is read.
#include "frontend/Flattener.h"

#include <algorithm>

namespace ldae::frontend {

namespace {

void assignedNames(const std::vector<ast::Statement> &list,
                   std::vector<const ast::Expr *> &out);

/// The names statement `st` assigns, in order of first assignment.
void assignedNames(const ast::Statement &st,
                   std::vector<const ast::Expr *> &out) {
  auto add = [&](const ast::Expr *target) {
    if (!target || target->kind != ast::ExprKind::Ref)
      return;
    for (const ast::Expr *seen : out)
      if (seen->parts[0].name == target->parts[0].name)
        return;
    out.push_back(target);
  };
  if (st.kind == ast::StatementKind::Assign)
    add(st.lhs.get());
  for (const ast::ExprPtr &t : st.targets)
    add(t.get());
  for (const auto &branch : st.branches)
    assignedNames(branch, out);
}

/// The names the statements assign, in order of first assignment.
void assignedNames(const std::vector<ast::Statement> &list,
                   std::vector<const ast::Expr *> &out) {
  for (const ast::Statement &st : list)
    assignedNames(st, out);
}

/// The names the when-statements of `list` (at its top level, MLS 11.2.7)
/// assign: discrete-time whatever their type.
std::vector<std::string> whenAssignedNames(
    const std::vector<ast::Statement> &list) {
  std::vector<const ast::Expr *> targets;
  for (const ast::Statement &st : list)
    if (st.kind == ast::StatementKind::When)
      assignedNames(st, targets);
  std::vector<std::string> names;
  for (const ast::Expr *t : targets)
    names.push_back(t->parts[0].name);
  return names;
}

/// The variable an assignment target names, whatever its subscripts.
ast::ExprPtr wholeVariable(const ast::Expr &target) {
  auto whole = std::make_unique<ast::Expr>();
  whole->kind = ast::ExprKind::Ref;
  whole->loc = target.loc;
  whole->length = target.length;
  whole->parts.push_back(ast::RefPart{target.parts[0].name, {}});
  return whole;
}

/// A when-statement inside another statement (MLS 11.2.7 allows them at
/// the top level of an algorithm section only), or null.
const ast::Statement *nestedWhen(const std::vector<ast::Statement> &list,
                                 bool nested) {
  for (const ast::Statement &st : list) {
    if (st.kind == ast::StatementKind::When && nested)
      return &st;
    bool inside = nested || st.kind != ast::StatementKind::When;
    for (const auto &branch : st.branches)
      if (const ast::Statement *w = nestedWhen(branch, inside))
        return w;
  }
  return nullptr;
}

} // namespace

void Flattener::flattenAlgorithm(const std::vector<ast::Statement> &section,
                                 const Scope &scope, bool initial) {
  if (section.empty() || !scope.cls)
    return;
  // An initial algorithm holds no when-statement at all.
  if (const ast::Statement *w = nestedWhen(section, initial)) {
    report(DiagId::ErrMisplaced, SourceRange{w->loc, 4},
           {"when", "a model's equations and the top level of its algorithm "
                    "sections"});
    return;
  }
  std::vector<const ast::Expr *> targets;
  assignedNames(section, targets);
  // The assigned variables as locals: their current values (a discrete
  // variable's pre(), as a Real's that a when-statement assigns: a branch
  // that does not assign an element, `buf[i] := u` with i known at run
  // time, keeps it) or unassigned.
  Env env;
  std::vector<Value> variables;
  const std::vector<std::string> inWhen = whenAssignedNames(section);
  for (const ast::Expr *t : targets) {
    if (t->parts.size() != 1) {
      report(DiagId::ErrUnsupported, SourceRange{t->loc, t->length},
             {"assigning a component's member in a model's algorithm section"});
      return;
    }
    std::optional<Value> v = lower(*wholeVariable(*t), scope, nullptr);
    if (!v)
      return;
    Value start = *v;
    const bool assignedInWhen =
        std::find(inWhen.begin(), inWhen.end(), t->parts[0].name) !=
        inWhen.end();
    for (ir::ExprRef &e : start.elems) {
      bool discrete = e && e->kind() == ir::ExprKind::Variable &&
                      (model_->variables[e->var()].isDiscrete ||
                       assignedInWhen);
      e = discrete ? ctx().pre(e->var()) : nullptr;
    }
    env.set(t->parts[0].name, std::move(start));
    variables.push_back(std::move(*v));
  }
  std::vector<std::string> whenTargets, locals;
  for (const ast::Expr *t : targets)
    locals.push_back(t->parts[0].name);
  algorithmWhenTargets_ = &whenTargets;
  algorithmLocals_ = &locals;
  ExecResult ran = execStatements(section, *scope.cls, scope, env);
  algorithmWhenTargets_ = nullptr;
  algorithmLocals_ = nullptr;
  if (ran != ExecResult::Ok)
    return;
  // A name a when-statement assigns gets its values from the when-clause
  // only: an assignment outside the when-statements would be lost.
  std::vector<const ast::Expr *> outside;
  for (const ast::Statement &st : section)
    if (st.kind != ast::StatementKind::When)
      assignedNames(st, outside);
  for (const ast::Expr *t : outside)
    if (std::find(whenTargets.begin(), whenTargets.end(), t->parts[0].name) !=
        whenTargets.end()) {
      report(DiagId::ErrUnsupported, SourceRange{t->loc, t->length},
             {"assigning '" + t->parts[0].name +
              "' both inside and outside the when-statements of an "
              "algorithm section"});
      return;
    }
  EqSink sink;
  sink.out = initial ? &model_->initialEquations : &model_->equations;
  for (size_t k = 0; k < targets.size(); ++k) {
    const ast::Expr &t = *targets[k];
    if (std::find(whenTargets.begin(), whenTargets.end(), t.parts[0].name) !=
        whenTargets.end())
      continue; // its when-clause assigns it
    const Value &now = *env.find(t.parts[0].name);
    for (size_t i = 0; i < now.elems.size(); ++i) {
      if (!now.elems[i]) {
        report(DiagId::ErrAlgorithmUnassigned, SourceRange{t.loc, t.length},
               {t.parts[0].name});
        return;
      }
      ir::Equation e;
      e.residual = ctx().sub(variables[k].elems[i], now.elems[i]);
      e.loc = t.loc;
      e.component = scope.inst ? scope.inst->path : "";
      e.origin = initial ? ir::EquationOrigin::Initial
                         : ir::EquationOrigin::Declared;
      e.text = "algorithm: " + t.parts[0].name + " := ...";
      sink.out->push_back(std::move(e));
    }
  }
}

Flattener::ExecResult
Flattener::execWhenStatement(const ast::Statement &st, const ast::ClassDef &fn,
                             const Scope &scope, Env &env) {
  // `when c1 then ... elsewhen c2 then ... end when`: one clause per branch,
  // as for when-equations (FlattenEquations.cpp); the branch's statements
  // run in order on a copy of the locals, and each name they assign gets
  // `v = its value at the end of the branch` in the clause.
  for (size_t k = 0; k < st.conds.size(); ++k) {
    const ast::Expr &ce = *st.conds[k];
    std::optional<Value> c = lower(ce, scope, &env);
    if (!c)
      return ExecResult::Error;
    if (c->isString || c->elems.empty()) {
      report(DiagId::ErrExpectedScalar, SourceRange{ce.loc, ce.length},
             {"when-condition", "a string"});
      return ExecResult::Error;
    }
    ir::WhenClause clause;
    clause.condition = ctx().logicalOr(c->elems);
    clause.elements = c->elems;
    clause.elsewhen = k > 0;
    clause.loc = k == 0 ? st.loc : ce.loc;
    std::vector<const ast::Expr *> assigned;
    assignedNames(st.branches[k], assigned);
    Env branch = env;
    std::optional<ImpureContext> atStart;
    std::optional<FiringContext> firing;
    if (isInitialCall(ce))
      atStart.emplace(*this);
    else
      firing.emplace(*this);
    {
      WhenAssertsScope checkedWhereItFires(*this, &clause.asserts);
      if (execStatements(st.branches[k], fn, scope, branch) != ExecResult::Ok)
        return ExecResult::Error;
    }
    atStart.reset();
    for (const ast::Expr *t : assigned) {
      const std::string &name = t->parts[0].name;
      std::optional<Value> var = lower(*wholeVariable(*t), scope, nullptr);
      if (!var)
        return ExecResult::Error;
      const Value &now = *branch.find(name);
      for (size_t i = 0; i < now.elems.size(); ++i) {
        if (!now.elems[i])
          continue; // not assigned in this branch
        ir::Equation e;
        e.residual = ctx().sub(var->elems[i], now.elems[i]);
        e.loc = t->loc;
        e.component = scope.inst ? scope.inst->path : "";
        e.text = "algorithm: " + name + " := ...";
        clause.equations.push_back(std::move(e));
        clause.targets.push_back(var->elems[i]);
      }
      // After the statement the name reads the variable (its value after
      // the event).
      env.set(name, *var);
      algorithmWhenTargets_->push_back(name);
    }
    if (firing)
      keepImpureCalls(clause);
    model_->whenClauses.push_back(std::move(clause));
  }
  return ExecResult::Ok;
}

} // namespace ldae::frontend
