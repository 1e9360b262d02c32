// Expressions -> IR values: operators with Modelica's array semantics
// (element-wise + and -, scalar broadcast, matrix and vector products),
// if-expressions (decided at compile time when the condition is a
// parameter expression), array constructors and comprehensions, ranges,
// and compile-time evaluation of parameter expressions.
#include "frontend/Concatenate.h"
#include "frontend/Flattener.h"

#include "ir/Evaluate.h"
#include "ir/Query.h"

#include <cmath>

namespace ldae::frontend {
namespace {

/// Counts lowering recursion; the parser already bounds nesting, this is
/// the backstop for recursion through inlined functions and constants.
struct DepthGuard {
  unsigned &depth;
  explicit DepthGuard(unsigned &d) : depth(++d) {}
  ~DepthGuard() { --depth; }
};

constexpr unsigned kMaxLowerDepth = 4000;

const char *binOpText(ast::BinOp op) {
  switch (op) {
  case ast::BinOp::Add: return "+";
  case ast::BinOp::Sub: return "-";
  case ast::BinOp::Mul: return "*";
  case ast::BinOp::Div: return "/";
  case ast::BinOp::Pow: return "^";
  case ast::BinOp::EAdd: return ".+";
  case ast::BinOp::ESub: return ".-";
  case ast::BinOp::EMul: return ".*";
  case ast::BinOp::EDiv: return "./";
  case ast::BinOp::EPow: return ".^";
  case ast::BinOp::Lt: return "<";
  case ast::BinOp::Le: return "<=";
  case ast::BinOp::Gt: return ">";
  case ast::BinOp::Ge: return ">=";
  case ast::BinOp::Eq: return "==";
  case ast::BinOp::Ne: return "<>";
  case ast::BinOp::And: return "and";
  case ast::BinOp::Or: return "or";
  }
  return "?";
}

} // namespace

Diagnostic &Flattener::report(DiagId id, SourceRange range,
                              std::vector<std::string> args) {
  std::string key = diagnosticKey(id, range, args);
  if (!reported_.insert(key).second) {
    dropped_ = Diagnostic{};
    return dropped_;
  }
  Diagnostic &d = diags_.report(id, range, std::move(args));
  if (d.severity != Severity::Note)
    addInstanceNotes(d);
  return d;
}

void Flattener::addInstanceNotes(Diagnostic &d) {
  // Only where the text is not the model's own: there the instance names
  // in the message say enough.
  if (!instanceContext_ || !root_ || !root_->cls ||
      !d.range.begin.valid() || d.range.begin.file == root_->cls->file)
    return;
  constexpr int kMaxLevels = 12;
  int levels = 0;
  for (const InstNode *n = instanceContext_; n && n->decl; n = n->parent) {
    if (n->isLeaf() && !n->isArray() && n->parent && n->parent->decl)
      continue; // its class instance says where
    if (++levels > kMaxLevels)
      break;
    DiagnosticEngine::addNote(d, SourceRange{n->decl->loc, n->decl->length},
                              DiagId::NoteInInstance,
                              {n->path, n->typeName});
  }
}

bool Flattener::readsFailedParameter(ir::ExprRef e) const {
  if (failedParameters_.empty() || !e || e->isConstant())
    return false;
  for (ir::ParamId p : ir::freeParameters(e))
    if (failedParameters_.count(p))
      return true;
  return false;
}

std::optional<double> Flattener::constantValue(ir::ExprRef e,
                                               std::string *evalError) {
  if (!e)
    return std::nullopt;
  if (e->isConstant())
    return e->constant();
  if (ir::dependsOnTime(e))
    return std::nullopt;
  bool dependsOnVariable = false;
  ir::EvalEnv env;
  env.variable = [&](ir::VarKey) {
    dependsOnVariable = true;
    return 0.0;
  };
  env.pre = [&](ir::VarId) {
    dependsOnVariable = true;
    return 0.0;
  };
  env.parameter = [&](ir::ParamId p) {
    if (p >= model_->parameters.size())
      return 0.0;
    // Outside a binding, a value read now decides the model's structure.
    if (!readingBinding_)
      model_->parameters[p].structural = true;
    return model_->parameters[p].value;
  };
  Expected<double> r = ir::evaluate(e, env, model_.get());
  if (!r || dependsOnVariable) {
    if (!r && !dependsOnVariable && evalError)
      *evalError = r.error();
    return std::nullopt;
  }
  return *r;
}

std::optional<double> Flattener::evalConstant(const ast::Expr &e,
                                              const Scope &scope, Env *env,
                                              const std::string &what) {
  std::optional<Value> v = lower(e, scope, env);
  if (!v)
    return std::nullopt;
  if (v->isString || !v->shape.empty()) {
    report(DiagId::ErrExpectedScalar, SourceRange{e.loc, e.length},
           {what, v->isString ? "a string" : describeShape(v->shape)});
    return std::nullopt;
  }
  std::string evalError;
  std::optional<double> c = constantValue(v->scalarExpr(), &evalError);
  if (!c && !evalError.empty()) {
    report(DiagId::ErrValueNotANumber, SourceRange{e.loc, e.length},
           {what, evalError});
    return c;
  }
  if (c && !std::isfinite(*c)) {
    report(DiagId::ErrNotFinite, SourceRange{e.loc, e.length},
           {what, fmtInteger(*c)});
    return std::nullopt;
  }
  if (!c) {
    std::vector<ir::VarKey> vars = ir::freeVariables(v->scalarExpr());
    if (!vars.empty()) {
      Diagnostic &d = report(DiagId::ErrNotParameterExpr,
                             SourceRange{e.loc, e.length}, {what});
      const ir::Variable &var = model_->variables[vars[0].var];
      DiagnosticEngine::addNote(d, var.loc, DiagId::NoteIsVariable, {var.name});
    } else {
      report(DiagId::ErrNotParameterExpr, SourceRange{e.loc, e.length}, {what});
    }
  }
  return c;
}

std::optional<int64_t> Flattener::evalInteger(const ast::Expr &e,
                                              const Scope &scope, Env *env,
                                              const std::string &what) {
  std::optional<double> v = evalConstant(e, scope, env, what);
  if (!v)
    return std::nullopt;
  if (*v != std::floor(*v) || std::abs(*v) > 9e15) {
    report(DiagId::ErrExpectedInteger, SourceRange{e.loc, e.length},
           {what, fmtInteger(*v)});
    return std::nullopt;
  }
  return static_cast<int64_t>(*v);
}

std::optional<Value> Flattener::lowerModValue(const Mod &mod) {
  if (!mod.value)
    return std::nullopt;
  auto key = std::make_tuple(mod.value, mod.scope.inst, mod.scope.cls);
  auto it = modValueCache_.find(key);
  Value v;
  if (it != modValueCache_.end()) {
    v = it->second;
  } else {
    std::optional<Value> lowered = lower(*mod.value, mod.scope, nullptr);
    if (!lowered)
      return std::nullopt;
    v = *lowered;
    modValueCache_.emplace(key, v);
  }
  for (int64_t idx : mod.index) {
    if (v.shape.empty() || v.isString)
      break; // a scalar applies to every element
    if (idx < 1 || idx > v.shape[0]) {
      report(DiagId::ErrModifierSize, SourceRange{mod.loc, mod.length},
             {describeShape(v.shape), std::to_string(idx)});
      return std::nullopt;
    }
    v = v.row(idx - 1);
  }
  return v;
}

std::optional<std::vector<double>>
Flattener::iteratorValues(const ast::ForIndex &it, const Scope &scope,
                          Env *env) {
  if (!it.range) {
    report(DiagId::ErrUnsupported, it.loc, {"for-loops without 'in range'"});
    return std::nullopt;
  }
  // `for e in E`: the literals of an enumeration, 1 ... n.
  if (const ast::ClassDef *en =
          env && it.range->kind == ast::ExprKind::Ref &&
                  env->find(it.range->parts[0].name)
              ? nullptr
              : enumerationNamed(*it.range, scope)) {
    std::vector<double> values;
    for (size_t k = 1; k <= en->enumLiterals.size(); ++k)
      values.push_back(double(k));
    return values;
  }
  std::optional<Value> v = lower(*it.range, scope, env);
  if (!v)
    return std::nullopt;
  if (v->isString || v->shape.size() > 1) {
    report(DiagId::ErrExpectedScalar, SourceRange{it.range->loc, it.range->length},
           {"range of '" + it.name + "'", "a vector"});
    return std::nullopt;
  }
  std::vector<double> values;
  values.reserve(v->elems.size());
  for (ir::ExprRef e : v->elems) {
    std::optional<double> c = constantValue(e);
    if (!c) {
      report(DiagId::ErrNotParameterExpr,
             SourceRange{it.range->loc, it.range->length},
             {"range of '" + it.name + "'"});
      return std::nullopt;
    }
    values.push_back(*c);
  }
  return values;
}

/// `*` with Modelica's meaning on vectors and matrices.
static std::optional<Value> multiply(Flattener &f, const Value &a,
                                     const Value &b, const ast::Expr &where) {
  ir::ExprContext &ctx = f.ctx();
  auto mul = [&](ir::ExprRef x, ir::ExprRef y) { return ctx.mul(x, y); };
  if (a.shape.empty() || b.shape.empty())
    return f.map2Value(a, b, mul, where, "*");
  size_t ra = a.shape.size(), rb = b.shape.size();
  if (ra > 2 || rb > 2) {
    f.report(DiagId::ErrShapeMismatch, SourceRange{where.loc, where.length},
             {"*", describeShape(a.shape), describeShape(b.shape)});
    return std::nullopt;
  }
  int64_t inner = a.shape.back();
  int64_t innerB = b.shape[0];
  if (inner != innerB) {
    f.report(DiagId::ErrShapeMismatch, SourceRange{where.loc, where.length},
             {"*", describeShape(a.shape), describeShape(b.shape)});
    return std::nullopt;
  }
  int64_t rows = ra == 2 ? a.shape[0] : 1;
  int64_t cols = rb == 2 ? b.shape[1] : 1;
  Value r;
  if (ra == 2)
    r.shape.push_back(rows);
  if (rb == 2)
    r.shape.push_back(cols);
  for (int64_t i = 0; i < rows; ++i)
    for (int64_t j = 0; j < cols; ++j) {
      std::vector<ir::ExprRef> terms;
      for (int64_t k = 0; k < inner; ++k)
        terms.push_back(ctx.mul(a.elems[i * inner + k], b.elems[k * cols + j]));
      r.elems.push_back(ctx.add(terms));
    }
  return r;
}

std::optional<Value> Flattener::lower(const ast::Expr &e, const Scope &scope,
                                      Env *env) {
  DepthGuard guard(lowerDepth);
  if (lowerDepth > kMaxLowerDepth) {
    report(DiagId::ErrNestingTooDeep, e.loc, {std::to_string(kMaxLowerDepth)});
    return std::nullopt;
  }
  ir::ExprContext &c = ctx();
  switch (e.kind) {
  case ast::ExprKind::Number:
    return Value::scalar(c.constant(e.number));
  case ast::ExprKind::String:
    return Value::string(e.text);
  case ast::ExprKind::Bool:
    return Value::scalar(c.constant(e.boolean ? 1 : 0));
  case ast::ExprKind::Ref:
    return lowerRef(e, scope, env);
  case ast::ExprKind::End:
    if (endStack.empty()) {
      report(DiagId::ErrMisplaced, e.loc, {"end", "a subscript"});
      return std::nullopt;
    }
    return Value::scalar(c.constant(static_cast<double>(endStack.back())));
  case ast::ExprKind::Colon:
    report(DiagId::ErrMisplaced, e.loc, {":", "a subscript"});
    return std::nullopt;
  case ast::ExprKind::Tuple:
    if (e.ops.size() == 1 && e.ops[0])
      return lower(*e.ops[0], scope, env);
    report(DiagId::ErrMisplaced, e.loc, {"(a, b)", "the left side of a call"});
    return std::nullopt;
  case ast::ExprKind::Call:
    return lowerCall(e, scope, env);
  case ast::ExprKind::Unary: {
    std::optional<Value> a = lower(*e.ops[0], scope, env);
    if (!a)
      return std::nullopt;
    if (a->isString) {
      report(DiagId::ErrStringOperand, SourceRange{e.loc, e.length},
             {e.unOp == ast::UnOp::Not ? "not" : "-"});
      return std::nullopt;
    }
    if (e.unOp == ast::UnOp::Plus)
      return a;
    if (e.unOp == ast::UnOp::Neg)
      return map1Value(*a, [&](ir::ExprRef x) { return c.neg(x); });
    return map1Value(*a, [&](ir::ExprRef x) { return c.logicalNot(x); });
  }
  case ast::ExprKind::Sum: {
    std::vector<Value> values;
    bool scalars = true, strings = true;
    for (const auto &op : e.ops) {
      std::optional<Value> v = lower(*op, scope, env);
      if (!v)
        return std::nullopt;
      scalars = scalars && v->isScalar();
      strings = strings && v->isString;
      values.push_back(std::move(*v));
    }
    if (scalars) {
      // One n-ary sum, as the IR keeps it.
      std::vector<ir::ExprRef> sum;
      for (size_t i = 0; i < values.size(); ++i)
        sum.push_back(e.negated[i] ? c.neg(values[i].elems[0])
                                   : values[i].elems[0]);
      return Value::scalar(c.add(sum));
    }
    bool anyMinus = false;
    for (bool n : e.negated)
      anyMinus = anyMinus || n;
    if (strings && !anyMinus) {
      std::string s;
      for (const Value &v : values)
        s += v.str;
      return Value::string(s);
    }
    Value acc;
    for (size_t i = 0; i < values.size(); ++i) {
      if (values[i].isString) {
        report(DiagId::ErrStringOperand,
               SourceRange{e.ops[i]->loc, e.ops[i]->length},
               {e.negated[i] ? "-" : "+"});
        return std::nullopt;
      }
      bool negate = e.negated[i];
      if (i == 0) {
        acc = negate ? map1Value(values[0], [&](ir::ExprRef x) { return c.neg(x); })
                     : values[0];
        continue;
      }
      std::optional<Value> next = map2Value(
          acc, values[i],
          [&](ir::ExprRef p, ir::ExprRef q) {
            return negate ? c.sub(p, q) : c.add(p, q);
          },
          e, negate ? "-" : "+");
      if (!next)
        return std::nullopt;
      acc = std::move(*next);
    }
    return acc;
  }
  case ast::ExprKind::Binary: {
    std::optional<Value> a = lower(*e.ops[0], scope, env);
    if (!a)
      return std::nullopt;
    // `false and b`, `true or b` with the left side known when compiling
    // do not need b (MSL's tables: `tableOnFile and fileName <> "NoName"
    // and not isEmpty(fileName)`, b a string function ldaec cannot inline).
    if ((e.binOp == ast::BinOp::And || e.binOp == ast::BinOp::Or) &&
        a->isScalar())
      if (std::optional<double> known = constantValue(a->scalarExpr());
          known && (*known != 0) == (e.binOp == ast::BinOp::Or))
        return Value::scalar(c.constant(*known != 0 ? 1 : 0));
    std::optional<Value> b = lower(*e.ops[1], scope, env);
    if (!b)
      return std::nullopt;
    const char *op = binOpText(e.binOp);
    if (a->isString || b->isString) {
      if (e.binOp == ast::BinOp::Add && a->isString && b->isString)
        return Value::string(a->str + b->str);
      // Strings are known when compiling: a comparison is a constant.
      if (a->isString && b->isString) {
        int order = a->str.compare(b->str);
        std::optional<bool> holds;
        switch (e.binOp) {
        case ast::BinOp::Eq: holds = order == 0; break;
        case ast::BinOp::Ne: holds = order != 0; break;
        case ast::BinOp::Lt: holds = order < 0; break;
        case ast::BinOp::Le: holds = order <= 0; break;
        case ast::BinOp::Gt: holds = order > 0; break;
        case ast::BinOp::Ge: holds = order >= 0; break;
        default: break;
        }
        if (holds)
          return Value::scalar(c.constant(*holds ? 1 : 0));
      }
      report(DiagId::ErrStringOperand, SourceRange{e.loc, e.length}, {op});
      return std::nullopt;
    }
    auto cmp = [&](ir::CompareKind k) {
      return map2Value(*a, *b,
                       [&](ir::ExprRef x, ir::ExprRef y) {
                         return c.compare(k, x, y);
                       },
                       e, op);
    };
    switch (e.binOp) {
    case ast::BinOp::Add:
    case ast::BinOp::EAdd:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.add(x, y); }, e, op);
    case ast::BinOp::Sub:
    case ast::BinOp::ESub:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.sub(x, y); }, e, op);
    case ast::BinOp::Mul:
      return multiply(*this, *a, *b, e);
    case ast::BinOp::EMul:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.mul(x, y); }, e, op);
    case ast::BinOp::Div:
    case ast::BinOp::EDiv:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.div(x, y); }, e, op);
    case ast::BinOp::Pow:
    case ast::BinOp::EPow:
      if (e.binOp == ast::BinOp::Pow && !a->shape.empty()) {
        report(DiagId::ErrUnsupported, e.loc, {"matrix powers"});
        return std::nullopt;
      }
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.pow(x, y); }, e, op);
    case ast::BinOp::Lt:
      return cmp(ir::CompareKind::Lt);
    case ast::BinOp::Le:
      return cmp(ir::CompareKind::Le);
    case ast::BinOp::Gt:
      return cmp(ir::CompareKind::Gt);
    case ast::BinOp::Ge:
      return cmp(ir::CompareKind::Ge);
    case ast::BinOp::Eq:
      return cmp(ir::CompareKind::Eq);
    case ast::BinOp::Ne:
      return cmp(ir::CompareKind::Ne);
    case ast::BinOp::And:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.logicalAnd(x, y); },
                  e, op);
    case ast::BinOp::Or:
      return map2Value(*a, *b,
                  [&](ir::ExprRef x, ir::ExprRef y) { return c.logicalOr(x, y); },
                  e, op);
    }
    return std::nullopt;
  }
  case ast::ExprKind::If: {
    // ops: cond, then, {cond, then}, else. Parameter conditions pick a
    // branch now; only the chosen branch has to be valid.
    size_t pairs = (e.ops.size() - 1) / 2;
    std::vector<ir::ExprRef> conds;
    std::vector<Value> values;
    // Each branch is lowered under the condition that takes it, so that a
    // check inside it (a run-time subscript's range) holds only there.
    const ir::ExprRef outerGuard = branchGuard_;
    ir::ExprRef notEarlier = outerGuard;
    auto guarded = [&](ir::ExprRef a, ir::ExprRef b) {
      return a ? c.logicalAnd(a, b) : b;
    };
    struct GuardRestore {
      ir::ExprRef &guard, saved;
      ~GuardRestore() { guard = saved; }
    } restore{branchGuard_, outerGuard};
    for (size_t k = 0; k < pairs; ++k) {
      branchGuard_ = notEarlier;
      std::optional<Value> cond = lower(*e.ops[2 * k], scope, env);
      if (!cond)
        return std::nullopt;
      if (!cond->isScalar()) {
        report(DiagId::ErrExpectedScalar,
               SourceRange{e.ops[2 * k]->loc, e.ops[2 * k]->length},
               {"condition", describeShape(cond->shape)});
        return std::nullopt;
      }
      std::optional<double> known = constantValue(cond->scalarExpr());
      if (known && *known == 0)
        continue;
      branchGuard_ =
          known ? notEarlier : guarded(notEarlier, cond->scalarExpr());
      std::optional<Value> v = lower(*e.ops[2 * k + 1], scope, env);
      if (!v)
        return std::nullopt;
      if (known && conds.empty())
        return v;
      if (known) {
        values.push_back(*v);
        conds.push_back(nullptr);
        break;
      }
      conds.push_back(cond->scalarExpr());
      values.push_back(*v);
      notEarlier = guarded(notEarlier, c.logicalNot(cond->scalarExpr()));
    }
    if (conds.empty() || conds.back() != nullptr) {
      branchGuard_ = notEarlier;
      std::optional<Value> v = lower(*e.ops.back(), scope, env);
      if (!v)
        return std::nullopt;
      if (conds.empty())
        return v;
      values.push_back(*v);
      conds.push_back(nullptr);
    }
    Value result = values.back();
    for (size_t k = conds.size() - 1; k-- > 0;) {
      const Value &then = values[k];
      if (then.isString || result.isString || then.shape != result.shape) {
        report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
               {"if", describeShape(then.shape), describeShape(result.shape)});
        return std::nullopt;
      }
      for (size_t i = 0; i < result.elems.size(); ++i)
        result.elems[i] = c.ifThenElse(conds[k], then.elems[i], result.elems[i]);
    }
    return result;
  }
  case ast::ExprKind::Array: {
    std::vector<Value> items;
    if (!e.iterators.empty()) {
      // {expr for i in r, j in s}: the first iterator is the outer index.
      Env local{env, {}};
      std::vector<int64_t> outer;
      std::function<bool(size_t)> iterate = [&](size_t k) -> bool {
        if (k == e.iterators.size()) {
          std::optional<Value> v = lower(*e.ops[0], scope, &local);
          if (!v)
            return false;
          items.push_back(std::move(*v));
          return true;
        }
        auto values = iteratorValues(e.iterators[k], scope, &local);
        if (!values)
          return false;
        if (outer.size() <= k)
          outer.push_back(static_cast<int64_t>(values->size()));
        for (double x : *values) {
          local.set(e.iterators[k].name, Value::scalar(c.constant(x)));
          if (!iterate(k + 1) || overBudget())
            return false;
        }
        return true;
      };
      if (!iterate(0))
        return std::nullopt;
      Value r;
      r.shape = outer;
      if (!items.empty())
        r.shape.insert(r.shape.end(), items[0].shape.begin(), items[0].shape.end());
      for (const Value &v : items)
        r.elems.insert(r.elems.end(), v.elems.begin(), v.elems.end());
      return r;
    }
    for (const auto &op : e.ops) {
      std::optional<Value> v = lower(*op, scope, env);
      if (!v)
        return std::nullopt;
      if (v->isString) {
        report(DiagId::ErrStringOperand, SourceRange{op->loc, op->length}, {"{}"});
        return std::nullopt;
      }
      if (!items.empty() && v->shape != items[0].shape) {
        report(DiagId::ErrShapeMismatch, SourceRange{op->loc, op->length},
               {"{}", describeShape(items[0].shape), describeShape(v->shape)});
        return std::nullopt;
      }
      items.push_back(std::move(*v));
    }
    Value r;
    r.shape.push_back(static_cast<int64_t>(items.size()));
    if (!items.empty())
      r.shape.insert(r.shape.end(), items[0].shape.begin(), items[0].shape.end());
    for (const Value &v : items)
      r.elems.insert(r.elems.end(), v.elems.begin(), v.elems.end());
    return r;
  }
  case ast::ExprKind::Matrix: {
    // MLS 10.4.2: [a, b; c, d] is cat(1, cat(2, a, b), cat(2, c, d)),
    // every element promoted to at least two dimensions (MSL's Digital
    // tables: [ {{{...}}} ] of a 9x4x4 array).
    std::vector<std::vector<Value>> rows;
    size_t ndims = 2;
    for (const auto &row : e.rows) {
      rows.emplace_back();
      for (const auto &x : row) {
        std::optional<Value> v = lower(*x, scope, env);
        if (!v)
          return std::nullopt;
        if (v->isString) {
          report(DiagId::ErrStringOperand, SourceRange{x->loc, x->length},
                 {"[]"});
          return std::nullopt;
        }
        ndims = std::max(ndims, v->shape.size());
        rows.back().push_back(std::move(*v));
      }
    }
    if (rows.empty() || std::any_of(rows.begin(), rows.end(),
                                    [](const auto &r) { return r.empty(); })) {
      Value r;
      r.shape = {static_cast<int64_t>(rows.size()), 0};
      return r;
    }
    std::pair<std::string, std::string> mismatch;
    std::vector<Value> joined;
    for (std::vector<Value> &row : rows) {
      for (Value &v : row)
        v = promote(std::move(v), ndims);
      std::optional<Value> r = concatenate(row, 1, mismatch);
      if (!r) {
        report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
               {"[,]", mismatch.first, mismatch.second});
        return std::nullopt;
      }
      joined.push_back(std::move(*r));
    }
    std::optional<Value> r = concatenate(joined, 0, mismatch);
    if (!r) {
      report(DiagId::ErrShapeMismatch, SourceRange{e.loc, e.length},
             {"[;]", mismatch.first, mismatch.second});
      return std::nullopt;
    }
    return r;
  }
  case ast::ExprKind::Range: {
    std::vector<double> parts;
    for (const auto &op : e.ops) {
      std::optional<double> v = evalConstant(*op, scope, env, "range bound");
      if (!v)
        return std::nullopt;
      parts.push_back(*v);
    }
    double start = parts[0], stop = parts.back();
    double step = parts.size() == 3 ? parts[1] : 1;
    if (step == 0 || !std::isfinite(start) || !std::isfinite(stop) ||
        !std::isfinite(step)) {
      report(DiagId::ErrBadRange, SourceRange{e.loc, e.length}, {});
      return std::nullopt;
    }
    double count = std::floor((stop - start) / step + 1e-9) + 1;
    if (count > static_cast<double>(kMaxArrayElements)) {
      report(DiagId::ErrArrayTooLarge, SourceRange{e.loc, e.length},
             {"range", std::to_string(kMaxArrayElements)});
      return std::nullopt;
    }
    Value r;
    int64_t n = count > 0 ? static_cast<int64_t>(count) : 0;
    r.shape.push_back(n);
    for (int64_t i = 0; i < n; ++i)
      r.elems.push_back(c.constant(start + static_cast<double>(i) * step));
    return r;
  }
  }
  return std::nullopt;
}

} // namespace ldae::frontend
