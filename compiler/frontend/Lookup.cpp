// Name lookup for component references: local names (iterators, function
// variables), then the components of the instance, then the built-in
// names, then classes and package constants by the lexical rules of
// ClassTable. Subscripts select elements of arrays of values and of
// components; `end` in a subscript is that dimension's size.
#include "frontend/Flattener.h"

#include <cmath>

namespace ldae::frontend {

const FunctionValue *Env::findFunction(const std::string &name) const {
  for (const Env *e = this; e; e = e->parent)
    for (const auto &[n, f] : e->functions)
      if (n == name)
        return &f;
  return nullptr;
}

Value *Env::find(const std::string &name) {
  for (Env *e = this; e; e = e->parent)
    for (auto &[n, v] : e->vars)
      if (n == name)
        return &v;
  return nullptr;
}

void Env::set(const std::string &name, Value v) {
  for (auto &[n, old] : vars)
    if (n == name) {
      old = std::move(v);
      return;
    }
  vars.emplace_back(name, std::move(v));
}

std::vector<int64_t> elementSubscripts(const std::vector<int64_t> &dims,
                                       int64_t index) {
  std::vector<int64_t> subs(dims.size());
  for (size_t k = dims.size(); k-- > 0;) {
    subs[k] = dims[k] ? index % dims[k] + 1 : 1;
    index = dims[k] ? index / dims[k] : 0;
  }
  return subs;
}

std::string elementName(const std::string &base,
                        const std::vector<int64_t> &dims, int64_t index) {
  if (dims.empty())
    return base;
  std::string s = base + "[";
  std::vector<int64_t> subs = elementSubscripts(dims, index);
  for (size_t k = 0; k < subs.size(); ++k)
    s += (k ? "," : "") + std::to_string(subs[k]);
  return s + "]";
}

bool Flattener::applySubscripts(const std::vector<ast::ExprPtr> &subs,
                                const std::vector<int64_t> &dims,
                                const std::string &what, const Scope &scope,
                                Env *env, std::vector<int64_t> &outShape,
                                std::vector<int64_t> &outOffsets,
                                SourceLoc loc,
                                std::vector<RunTimeSubscript> *runTime) {
  if (subs.size() > dims.size()) {
    report(DiagId::ErrTooManySubscripts, loc,
                  {what, std::to_string(dims.size()),
                   std::to_string(subs.size())});
    return false;
  }
  // Indices (0-based) chosen per dimension.
  std::vector<std::vector<int64_t>> chosen(dims.size());
  for (size_t k = 0; k < dims.size(); ++k) {
    if (k >= subs.size() || subs[k]->kind == ast::ExprKind::Colon) {
      for (int64_t i = 0; i < dims[k]; ++i)
        chosen[k].push_back(i);
      outShape.push_back(dims[k]);
      continue;
    }
    endStack.push_back(dims[k]);
    std::optional<Value> v = lower(*subs[k], scope, env);
    endStack.pop_back();
    if (!v)
      return false;
    if (v->isString) {
      report(DiagId::ErrSubscriptNotInteger, subs[k]->loc, {what});
      return false;
    }
    if (v->shape.size() > 1) {
      report(DiagId::ErrSubscriptNotInteger, subs[k]->loc, {what});
      return false;
    }
    std::string evalError;
    if (runTime && v->shape.empty() &&
        !constantValue(v->elems[0], &evalError)) {
      // Known at run time: keep the dimension whole; selectAtRunTime
      // picks the element. A constant that cannot be evaluated (x[i -
      // (0/0)]) is no value at run time either.
      if (!evalError.empty()) {
        report(DiagId::ErrValueNotANumber,
               SourceRange{subs[k]->loc, subs[k]->length},
               {"subscript of '" + what + "'", evalError});
        return false;
      }
      if (!isIntegerValued(v->elems[0])) {
        report(DiagId::ErrSubscriptNotInteger, subs[k]->loc, {what});
        return false;
      }
      for (int64_t i = 0; i < dims[k]; ++i)
        chosen[k].push_back(i);
      outShape.push_back(dims[k]);
      runTime->push_back({outShape.size() - 1, dims[k], v->elems[0], what,
                          SourceRange{subs[k]->loc, subs[k]->length}});
      continue;
    }
    for (ir::ExprRef e : v->elems) {
      std::optional<double> c = constantValue(e);
      if (!c) {
        report(DiagId::ErrSubscriptNotConstant,
                      SourceRange{subs[k]->loc, subs[k]->length}, {what});
        return false;
      }
      if (*c != std::floor(*c)) {
        report(DiagId::ErrSubscriptNotInteger, subs[k]->loc, {what});
        return false;
      }
      if (*c < 1 || *c > static_cast<double>(dims[k])) {
        report(DiagId::ErrIndexOutOfRange,
                      SourceRange{subs[k]->loc, subs[k]->length},
                      {fmtInteger(*c), what, std::to_string(dims[k])});
        return false;
      }
      chosen[k].push_back(static_cast<int64_t>(*c) - 1);
    }
    if (!v->shape.empty())
      outShape.push_back(static_cast<int64_t>(v->elems.size()));
  }
  // Row-major cartesian product of the choices.
  outOffsets.assign(1, 0);
  for (size_t k = 0; k < dims.size(); ++k) {
    std::vector<int64_t> next;
    next.reserve(outOffsets.size() * chosen[k].size());
    for (int64_t base : outOffsets)
      for (int64_t i : chosen[k])
        next.push_back(base * dims[k] + i);
    outOffsets = std::move(next);
  }
  return true;
}

std::optional<Selection>
Flattener::resolveInstancePath(const ast::Expr &ref, size_t firstPart,
                               InstNode *start, const Scope &scope, Env *env,
                               std::vector<RunTimeSubscript> *runTime) {
  Selection sel;
  sel.targets.push_back({start, -1});
  std::string written;
  for (size_t i = firstPart; i < ref.parts.size(); ++i) {
    const ast::RefPart &part = ref.parts[i];
    written += (written.empty() ? "" : ".") + part.name;
    Selection next;
    next.shape = sel.shape;
    bool first = true;
    for (const RefTarget &t : sel.targets) {
      InstNode *n = t.node;
      bool last = i + 1 == ref.parts.size();
      if (!(last ? ensureElaborated(*n, ref.loc) : ensureMembers(*n, ref.loc)))
        return std::nullopt;
      std::vector<int64_t> shape, offsets;
      if (!n->isArray() && !part.subscripts.empty()) {
        report(DiagId::ErrNotAnArray,
                      SourceRange{ref.loc, ref.length}, {written});
        return std::nullopt;
      }
      // Only an array of values is selected at run time, and its
      // dimensions are recorded once (every target has the same).
      std::vector<RunTimeSubscript> ignored;
      std::vector<RunTimeSubscript> *dynamic =
          runTime && n->isLeaf() && i + 1 == ref.parts.size()
              ? (first ? runTime : &ignored)
              : nullptr;
      size_t before = dynamic ? dynamic->size() : 0;
      if (!applySubscripts(part.subscripts, n->dims, written, scope, env,
                           shape, offsets, ref.loc, dynamic))
        return std::nullopt;
      if (dynamic)
        for (size_t d = before; d < dynamic->size(); ++d)
          (*dynamic)[d].axis += next.shape.size();
      if (first)
        next.shape.insert(next.shape.end(), shape.begin(), shape.end());
      first = false;
      for (int64_t off : offsets) {
        if (n->isLeaf())
          next.targets.push_back({n, off});
        else if (n->isArray())
          next.targets.push_back({n->elements[off].get(), -1});
        else
          next.targets.push_back({n, -1});
      }
    }
    sel = std::move(next);
    if (i + 1 == ref.parts.size())
      break;
    // Step into the member named by the next part.
    const std::string &member = ref.parts[i + 1].name;
    for (RefTarget &t : sel.targets) {
      InstNode *n = t.node;
      InstNode *found = n->isLeaf() ? nullptr : n->findMember(member);
      if (!found && n->findRemoved(member)) {
        reportRemoved(*n->findRemoved(member), SourceRange{ref.loc,
                                                           ref.length});
        return std::nullopt;
      }
      if (!found) {
        std::vector<std::string> names;
        for (const auto &m : n->members)
          names.push_back(m->name);
        std::string best = closestName(member, names);
        if (best.empty())
          report(DiagId::ErrNoMember, SourceRange{ref.loc, ref.length},
                        {member, written, n->typeName});
        else
          report(DiagId::ErrNoMemberSuggest,
                        SourceRange{ref.loc, ref.length},
                        {member, written, n->typeName, best});
        return std::nullopt;
      }
      t = {found, -1};
    }
  }
  return sel;
}

std::optional<Value>
Flattener::packageConstant(const ast::Component &comp,
                           const ast::ClassDef &owner, const ast::Expr &ref,
                           size_t part, const Scope &scope, Env *env) {
  std::string name = comp.name;
  if (comp.prefix.variability != ast::Variability::Constant &&
      comp.prefix.variability != ast::Variability::Parameter) {
    report(DiagId::ErrNotConstantRef, SourceRange{ref.loc, ref.length},
                  {ref.refName()});
    return std::nullopt;
  }
  auto cached = packageConstants_.find(&comp);
  Value value;
  if (cached != packageConstants_.end()) {
    value = cached->second;
  } else {
    if (packageConstantBusy_[&comp]) {
      report(DiagId::ErrCyclicDefinition, comp.loc, {name});
      return std::nullopt;
    }
    if (!comp.mod || !comp.mod->value) {
      report(DiagId::ErrConstantWithoutValue,
                    SourceRange{ref.loc, ref.length}, {ref.refName()});
      return std::nullopt;
    }
    packageConstantBusy_[&comp] = true;
    std::optional<Value> v = lower(*comp.mod->value, Scope{nullptr, &owner}, nullptr);
    packageConstantBusy_[&comp] = false;
    if (!v)
      return std::nullopt;
    value = *v;
    packageConstants_[&comp] = value;
  }
  if (part + 1 < ref.parts.size()) {
    report(DiagId::ErrNoMember, SourceRange{ref.loc, ref.length},
                  {ref.parts[part + 1].name, ref.parts[part].name, "Real"});
    return std::nullopt;
  }
  const auto &subs = ref.parts[part].subscripts;
  if (subs.empty() || value.isString)
    return value;
  std::vector<int64_t> shape, offsets;
  std::vector<RunTimeSubscript> runTime;
  if (!applySubscripts(subs, value.shape, ref.refName(), scope, env, shape,
                       offsets, ref.loc, &runTime))
    return std::nullopt;
  Value out;
  out.shape = shape;
  for (int64_t off : offsets)
    out.elems.push_back(value.elems[off]);
  return selectAtRunTime(std::move(out), runTime);
}

/// `StateSelect.prefer` and `AssertionLevel.warning`: values of the
/// built-in enumerations (MLS 4.9.5, 8.3.7): StateSelect's as the
/// attribute's index (never 0 ... always 4), AssertionLevel's as their
/// ordinal (warning 1, error 2).
static std::optional<double> builtinEnumerationValue(const ast::Expr &ref) {
  if (ref.parts.size() != 2)
    return std::nullopt;
  if (ref.parts[0].name == "StateSelect") {
    static const char *names[] = {"never", "avoid", "default", "prefer",
                                  "always"};
    for (int i = 0; i < 5; ++i)
      if (ref.parts[1].name == names[i])
        return i;
  }
  if (ref.parts[0].name == "AssertionLevel") {
    if (ref.parts[1].name == "warning")
      return 1;
    if (ref.parts[1].name == "error")
      return 2;
  }
  return std::nullopt;
}

std::optional<Value> Flattener::lowerRef(const ast::Expr &ref,
                                         const Scope &scope, Env *env) {
  const std::string &first = ref.parts[0].name;
  // Locals: iterators and function variables.
  if (!ref.global && env)
    if (Value *local = env->find(first)) {
      if (ref.parts.size() > 1) {
        report(DiagId::ErrNoMember, SourceRange{ref.loc, ref.length},
                      {ref.parts[1].name, first, "Real"});
        return std::nullopt;
      }
      Value v = *local;
      // Only the elements read must have values: `den2[i, 2] := 2 *
      // den2[i, 1]` fills an array element by element.
      auto assigned = [&](const Value &read) {
        for (ir::ExprRef e : read.elems)
          if (!e) {
            report(DiagId::ErrUsedBeforeAssigned,
                   SourceRange{ref.loc, ref.length}, {first});
            return false;
          }
        return true;
      };
      if (ref.parts[0].subscripts.empty())
        return assigned(v) ? std::optional<Value>(v) : std::nullopt;
      if (v.isString || v.shape.empty()) {
        report(DiagId::ErrNotAnArray, SourceRange{ref.loc, ref.length},
                      {first});
        return std::nullopt;
      }
      std::vector<int64_t> shape, offsets;
      std::vector<RunTimeSubscript> runTime;
      if (!applySubscripts(ref.parts[0].subscripts, v.shape, first, scope, env,
                           shape, offsets, ref.loc, &runTime))
        return std::nullopt;
      Value out;
      out.shape = shape;
      for (int64_t off : offsets)
        out.elems.push_back(v.elems[off]);
      if (!assigned(out))
        return std::nullopt;
      return selectAtRunTime(std::move(out), runTime);
    }
  // Components of the instance.
  if (!ref.global && scope.inst) {
    if (const InstNode *gone = scope.inst->findRemoved(first)) {
      reportRemoved(*gone, SourceRange{ref.loc, ref.length});
      return std::nullopt;
    }
    if (InstNode *member = scope.inst->findMember(first)) {
      std::vector<RunTimeSubscript> runTime;
      std::optional<Selection> sel =
          resolveInstancePath(ref, 0, member, scope, env, &runTime);
      if (!sel)
        return std::nullopt;
      Value v;
      v.shape = sel->shape;
      for (const RefTarget &t : sel->targets) {
        if (t.slot < 0) {
          report(DiagId::ErrComponentAsValue,
                        SourceRange{ref.loc, ref.length},
                        {ref.refName(), t.node->typeName});
          return std::nullopt;
        }
        // A scalar String parameter is its binding, known when compiling
        // (depth-limited: a binding may name itself).
        static thread_local unsigned stringDepth_ = 0;
        if (t.node->builtin == BuiltinType::String && sel->shape.empty() &&
            sel->targets.size() == 1 && t.node->mod && t.node->mod->value &&
            t.node->variability != ast::Variability::Continuous &&
            stringDepth_ < 16) {
          ++stringDepth_;
          std::optional<Value> bound =
              lower(*t.node->mod->value, t.node->mod->scope, nullptr);
          --stringDepth_;
          if (bound && bound->isString)
            return bound;
          if (!bound)
            return std::nullopt; // its binding's error is reported
        }
        if (t.node->builtin == BuiltinType::String ||
            t.slot >= static_cast<int64_t>(t.node->slots.size())) {
          report(DiagId::ErrStringComponent,
                        SourceRange{ref.loc, ref.length}, {ref.refName()});
          return std::nullopt;
        }
        const Slot &s = t.node->slots[t.slot];
        v.elems.push_back(s.isParam ? ctx().param(s.id) : ctx().var(s.id));
      }
      return selectAtRunTime(std::move(v), runTime);
    }
  }
  // Built-in names.
  if (!ref.global && ref.parts.size() == 1 && ref.parts[0].subscripts.empty()) {
    if (first == "time")
      return Value::scalar(ctx().time());
    if (first == "pi")
      return Value::scalar(ctx().constant(M_PI));
  }
  if (std::optional<double> ss = builtinEnumerationValue(ref))
    return Value::scalar(ctx().constant(*ss));
  // Classes and package constants.
  uint32_t file = scope.cls ? scope.cls->file : ref.loc.file;
  LexicalHit hit = ref.global ? classes_.lookup(first, nullptr, file)
                              : classes_.lookup(first, scope.cls, file);
  if (hit.comp)
    return packageConstant(*hit.comp, *hit.owner, ref, 0, scope, env);
  if (hit.cls) {
    const ast::ClassDef *cls = hit.cls;
    for (size_t i = 1; i < ref.parts.size(); ++i) {
      const std::string &name = ref.parts[i].name;
      // `E.b`: the position of the literal, 1 ... n.
      if (const ast::ClassDef *en = enumerationOf(cls)) {
        const auto &lits = en->enumLiterals;
        auto at = std::find(lits.begin(), lits.end(), name);
        if (at != lits.end() && i + 1 == ref.parts.size() &&
            ref.parts[i].subscripts.empty())
          return Value::scalar(ctx().constant(double(at - lits.begin() + 1)));
        std::string all;
        for (const std::string &l : lits)
          all += (all.empty() ? "" : ", ") + l;
        report(DiagId::ErrNoLiteral, SourceRange{ref.loc, ref.length},
               {name, cls->qualifiedName(), all});
        return std::nullopt;
      }
      if (const ast::ClassDef *inner = classes_.memberClass(*cls, name)) {
        cls = inner;
        continue;
      }
      const ast::ClassDef *owner = nullptr;
      if (const ast::Component *comp =
              classes_.memberComponent(*cls, name, &owner))
        return packageConstant(*comp, *owner, ref, i, scope, env);
      report(DiagId::ErrNoMember, SourceRange{ref.loc, ref.length},
                    {name, cls->qualifiedName(), cls->name});
      return std::nullopt;
    }
    report(DiagId::ErrClassAsValue, SourceRange{ref.loc, ref.length},
                  {ref.refName()});
    return std::nullopt;
  }
  reportUndefined(ref, scope, env);
  return std::nullopt;
}

std::optional<Selection>
Flattener::selectComponents(const ast::Expr &ref, const Scope &scope,
                            Env *env) {
  const std::string &first = ref.parts[0].name;
  if (!ref.global && scope.inst) {
    if (InstNode *member = scope.inst->findMember(first))
      return resolveInstancePath(ref, 0, member, scope, env);
  }
  reportUndefined(ref, scope, env);
  return std::nullopt;
}

const ast::ClassDef *Flattener::enumerationOf(const ast::ClassDef *cls) {
  for (unsigned guard = 0; cls && guard < kMaxInstanceDepth; ++guard) {
    if (cls->isEnumeration)
      return cls;
    if (!cls->isShort)
      return nullptr;
    cls = classes_.resolveClass(cls->shortBase, cls->parent, cls->file,
                                /*report=*/false);
  }
  return nullptr;
}

const ast::ClassDef *Flattener::enumerationNamed(const ast::Expr &e,
                                                 const Scope &scope) {
  if (e.kind != ast::ExprKind::Ref || e.parts.empty())
    return nullptr;
  ast::Name name;
  name.global = e.global;
  name.loc = e.loc;
  for (const ast::RefPart &p : e.parts) {
    if (!p.subscripts.empty())
      return nullptr;
    name.parts.push_back(p.name);
  }
  // A component or a local of that name is not a type name.
  if (!e.global && scope.inst && scope.inst->findMember(name.parts[0]))
    return nullptr;
  uint32_t file = scope.cls ? scope.cls->file : e.loc.file;
  return enumerationOf(
      classes_.resolveClass(name, scope.cls, file, /*report=*/false));
}

void Flattener::reportRemoved(const InstNode &removed, SourceRange range) {
  if (removed.inExpandable) {
    report(DiagId::ErrExpandableAbsent, range,
           {removed.name, removed.parent ? removed.parent->path : ""});
    return;
  }
  report(DiagId::ErrConditionalRemoved, range,
         {removed.name, removed.decl->conditionText});
}

void Flattener::reportUndefined(const ast::Expr &ref, const Scope &scope,
                                Env *env) {
  const std::string &first = ref.parts[0].name;
  SourceRange range{ref.loc, ref.length};
  if (const InstNode *gone =
          !ref.global && scope.inst ? scope.inst->findRemoved(first) : nullptr) {
    reportRemoved(*gone, range);
    return;
  }
  std::string best = suggest(first, scope, env);
  if (best.empty())
    report(DiagId::ErrUndefinedName, range, {first});
  else
    report(DiagId::ErrUndefinedNameSuggest, range, {first, best});
}

std::string Flattener::suggest(const std::string &name, const Scope &scope,
                               Env *env) {
  std::vector<std::string> names;
  for (Env *e = env; e; e = e->parent)
    for (const auto &[n, v] : e->vars)
      names.push_back(n);
  if (scope.inst)
    for (const auto &m : scope.inst->members)
      names.push_back(m->name);
  names.push_back("time");
  names.push_back("pi");
  classes_.visibleNames(scope.cls, scope.cls ? scope.cls->file : 0, names);
  return closestName(name, names);
}

} // namespace ldae::frontend
