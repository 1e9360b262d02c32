// The instance tree: every component of the model with its type resolved,
// its modifiers merged (the instantiating component over `extends`
// modifiers over the declaration over the type), its array sizes evaluated
// and, for Real/Integer/Boolean leaves, its scalars created as IR variables
// or parameters. Elaboration is on demand, so a declaration may use a
// parameter declared after it; a real cycle is an error.
#include "frontend/ExternalObject.h"
#include "frontend/Flattener.h"
#include "ir/Query.h"

#include <cmath>

namespace ldae::frontend {

ModPtr Mod::sub(const std::string &name) const {
  for (const auto &[n, m] : subs)
    if (n == name)
      return m;
  return nullptr;
}

ModPtr mergeMods(const ModPtr &outer, const ModPtr &inner) {
  if (!outer)
    return inner;
  if (!inner)
    return outer;
  auto m = std::make_shared<Mod>(*outer);
  if (!m->redeclare) {
    m->redeclare = inner->redeclare;
    m->redeclareScope = inner->redeclareScope;
  }
  if (!m->value) {
    m->value = inner->value;
    m->text = inner->text;
    m->loc = inner->loc;
    m->length = inner->length;
    m->scope = inner->scope;
    m->index = inner->index;
    m->each = inner->each;
  }
  for (const auto &[name, sub] : inner->subs) {
    bool found = false;
    for (auto &[n, s] : m->subs)
      if (n == name) {
        s = mergeMods(s, sub);
        found = true;
      }
    if (!found)
      m->subs.emplace_back(name, sub);
  }
  return m;
}

namespace {

/// The modifier seen by element `subs` (1-based) of an array: values not
/// marked `each` are indexed.
ModPtr indexMod(const ModPtr &mod, const std::vector<int64_t> &subs) {
  if (!mod || mod->each)
    return mod;
  auto m = std::make_shared<Mod>(*mod);
  if (m->value)
    m->index.insert(m->index.end(), subs.begin(), subs.end());
  for (auto &[name, sub] : m->subs)
    sub = indexMod(sub, subs);
  return m;
}

BuiltinType builtinNamed(const ast::Name &n) {
  if (n.parts.size() != 1)
    return BuiltinType::None;
  const std::string &s = n.parts[0];
  if (s == "Real")
    return BuiltinType::Real;
  // StateSelect and AssertionLevel, the built-in enumerations: their
  // values are integers (Lookup.cpp).
  if (s == "Integer" || s == "StateSelect" || s == "AssertionLevel")
    return BuiltinType::Integer;
  if (s == "Boolean")
    return BuiltinType::Boolean;
  if (s == "String")
    return BuiltinType::String;
  return BuiltinType::None;
}

std::string joinPath(const std::string &prefix, const std::string &name) {
  return prefix.empty() ? name : prefix + "." + name;
}

} // namespace

const std::vector<std::string> &
Flattener::attributeNames(BuiltinType t) const {
  static const std::vector<std::string> real = {
      "start",    "fixed",       "nominal",     "min", "max", "unit",
      "quantity", "displayUnit", "stateSelect", "unbounded"};
  static const std::vector<std::string> integer = {"start", "fixed", "min",
                                                   "max", "quantity"};
  static const std::vector<std::string> boolean = {"start", "fixed",
                                                   "quantity"};
  static const std::vector<std::string> string = {"start", "quantity"};
  switch (t) {
  case BuiltinType::Real:
    return real;
  case BuiltinType::Integer:
    return integer;
  case BuiltinType::Boolean:
    return boolean;
  default:
    return string;
  }
}

ModPtr Flattener::makeMod(const ast::Modification *m, const Scope &scope) {
  if (!m)
    return nullptr;
  auto mod = std::make_shared<Mod>();
  mod->value = m->value.get();
  mod->scope = scope;
  mod->loc = m->value ? m->value->loc : m->loc;
  mod->length = m->value ? m->value->length : 1;
  for (const ast::Modifier &arg : m->args) {
    if (arg.path.empty())
      continue;
    // `a.b.c = v` is `a(b(c = v))`; `redeclare T a(b = v)` is `a(b = v)`
    // with a's new declaration.
    ModPtr leaf = makeMod(arg.redeclared ? arg.redeclared->mod.get()
                                         : arg.mod.get(),
                          scope);
    auto inner = leaf ? std::make_shared<Mod>(*leaf) : std::make_shared<Mod>();
    if (arg.redeclared) {
      inner->redeclare = arg.redeclared.get();
      inner->redeclareScope = scope;
    }
    inner->each = arg.each;
    inner->text = arg.text;
    inner->nameLoc = arg.loc;
    inner->nameLength = arg.length;
    inner->scope = scope;
    if (!inner->value) {
      inner->loc = arg.loc;
      inner->length = arg.length;
    }
    ModPtr node = inner;
    for (size_t k = arg.path.size() - 1; k > 0; --k) {
      auto wrap = std::make_shared<Mod>();
      wrap->loc = arg.loc;
      wrap->nameLoc = arg.loc;
      wrap->nameLength = arg.length;
      wrap->scope = scope;
      wrap->subs.emplace_back(arg.path[k], node);
      node = wrap;
    }
    bool merged = false;
    for (auto &[n, s] : mod->subs)
      if (n == arg.path[0]) {
        s = mergeMods(node, s);
        merged = true;
      }
    if (!merged)
      mod->subs.emplace_back(arg.path[0], node);
  }
  return mod;
}

bool Flattener::ensureElaborated(InstNode &node, SourceLoc usedAt) {
  switch (node.state) {
  case InstNode::State::Done:
    return true;
  case InstNode::State::Failed:
    return false;
  case InstNode::State::Prepared:
    finishPrepared(node);
    return node.state == InstNode::State::Done;
  case InstNode::State::Elaborating:
    if (node.membersReady)
      return true;
    report(DiagId::ErrCyclicDefinition, usedAt,
                  {node.path.empty() ? node.name : node.path});
    return false;
  case InstNode::State::Declared:
    break;
  }
  elaborateComponent(node, false);
  return node.state == InstNode::State::Done;
}

bool Flattener::ensureMembers(InstNode &node, SourceLoc usedAt) {
  if (node.state == InstNode::State::Prepared)
    return true;
  if (node.state == InstNode::State::Declared) {
    elaborateComponent(node, true);
    return node.state == InstNode::State::Prepared ||
           node.state == InstNode::State::Done;
  }
  return ensureElaborated(node, usedAt);
}

void Flattener::finishPrepared(InstNode &node) {
  InstanceContext context(*this, &node);
  node.state = InstNode::State::Elaborating;
  if (node.isArray()) {
    for (auto &elem : node.elements)
      if (elem->state == InstNode::State::Prepared) {
        elem->state = InstNode::State::Elaborating;
        elaborateMembers(*elem);
        elem->state = InstNode::State::Done;
      }
  } else {
    elaborateMembers(node);
  }
  node.state = InstNode::State::Done;
}

bool Flattener::resolveType(InstNode &node) {
  const ast::Component &d = *node.decl;
  node.typeName = d.typeName.str();
  const ast::ClassDef *scope = node.declClass;
  uint32_t file = node.declClass ? node.declClass->file : d.loc.file;
  ast::Name cur = d.typeName;
  std::vector<ModPtr> typeMods;
  std::vector<int64_t> typeDims;
  std::vector<const ast::ClassDef *> seen; // short classes on the way
  for (;;) {
    if (!cur.global)
      if (BuiltinType b = builtinNamed(cur); b != BuiltinType::None) {
        node.builtin = b;
        break;
      }
    const ast::ClassDef *cls = classes_.resolveClass(cur, scope, file);
    if (!cls)
      return false;
    if (cls->kind == ast::ClassKind::Connector)
      node.isConnector = true;
    if (cls->isEnumeration) {
      if (cls->enumLiterals.empty()) {
        report(DiagId::ErrUnsupported, d.typeName.loc,
               {"enumeration(:) types"});
        return false;
      }
      node.builtin = BuiltinType::Integer;
      node.enumeration = cls;
      break;
    }
    if (!cls->isShort && isExternalObject(*cls)) {
      node.builtin = BuiltinType::Real; // the handle (ExternalObject.h)
      node.externalObject = true;
      break;
    }
    if (!cls->isShort) {
      if (cls->kind == ast::ClassKind::Function ||
          cls->kind == ast::ClassKind::Package ||
          cls->kind == ast::ClassKind::Operator) {
        report(DiagId::ErrNotAType, d.typeName.loc,
                      {node.typeName, ast::classKindName(cls->kind)});
        return false;
      }
      node.cls = cls;
      break;
    }
    if (std::find(seen.begin(), seen.end(), cls) != seen.end()) {
      report(DiagId::ErrRecursiveType, d.typeName.loc, {node.typeName});
      return false;
    }
    if (seen.size() >= kMaxInstanceDepth) {
      report(DiagId::ErrTypeTooDeep, d.typeName.loc,
             {node.typeName, std::to_string(kMaxInstanceDepth)});
      return false;
    }
    seen.push_back(cls);
    Scope typeScope{nullptr, cls->parent};
    if (cls->shortMod)
      typeMods.push_back(makeMod(cls->shortMod.get(), typeScope));
    for (const auto &dim : cls->shortDims) {
      std::optional<int64_t> n =
          evalInteger(*dim, typeScope, nullptr, "array size of '" + cls->name + "'");
      if (!n)
        return false;
      typeDims.push_back(*n);
    }
    if (node.causality == ast::Causality::None)
      node.causality = cls->shortPrefix.causality;
    scope = cls->parent;
    file = cls->file;
    cur = cls->shortBase;
  }
  ModPtr typeMod;
  for (auto it = typeMods.rbegin(); it != typeMods.rend(); ++it)
    typeMod = mergeMods(*it, typeMod);
  node.mod = mergeMods(node.mod, typeMod);
  node.dims.insert(node.dims.end(), typeDims.begin(), typeDims.end());
  return true;
}

bool Flattener::countInstances(int64_t count, const InstNode &node) {
  instances_ += static_cast<size_t>(count);
  if (instances_ <= kMaxInstances)
    return true;
  if (!budgetReported_) {
    budgetReported_ = true;
    report(DiagId::ErrTooManyInstances,
           SourceRange{node.decl->loc, node.decl->length},
           {std::to_string(kMaxInstances), node.path});
  }
  return false;
}

void Flattener::elaborateComponent(InstNode &node, bool membersOnly) {
  InstanceContext context(*this, &node);
  node.state = InstNode::State::Elaborating;
  const ast::Component &d = *node.decl;
  // A parameter's sizes may come from its value (`parameter Real A[:, :]
  // = readRealMatrix(...)`): an impure call is made there too.
  std::optional<ImpureContext> impure;
  if (d.prefix.variability == ast::Variability::Parameter)
    impure.emplace(*this);
  node.flow = d.prefix.flow || (node.parent && node.parent->flow);
  node.variability = d.prefix.variability;
  if (node.parent && node.parent->isParameterLike() &&
      !node.isParameterLike())
    node.variability = node.parent->variability;
  node.causality = d.prefix.causality;

  // Array sizes are evaluated where the declaration is written.
  Scope declScope{node.parent, node.declClass};
  // `Real table[:, 2] = [...]`: a size given as `:` is the binding's.
  std::optional<Value> binding;
  for (size_t k = 0; k < d.dims.size(); ++k) {
    const auto &dim = d.dims[k];
    if (dim->kind == ast::ExprKind::Colon) {
      if (!binding && node.mod && node.mod->value)
        binding = lowerModValue(*node.mod);
      if (!binding || binding->shape.size() != d.dims.size()) {
        report(DiagId::ErrArraySizeMissing, dim->loc, {d.name});
        node.state = InstNode::State::Failed;
        return;
      }
      node.dims.push_back(binding->shape[k]);
      continue;
    }
    // `A[:, size(A, 1)] = [1, 0; 0, 1]` (MSL's StateSpace): a size of
    // the component itself is its binding's.
    if (dim->kind == ast::ExprKind::Call && dim->text == "size" &&
        dim->args.size() == 2 && dim->args[0].name.empty() &&
        dim->args[1].name.empty() &&
        dim->args[0].value->kind == ast::ExprKind::Ref &&
        dim->args[0].value->parts.size() == 1 &&
        dim->args[0].value->parts[0].name == d.name &&
        dim->args[0].value->parts[0].subscripts.empty() &&
        dim->args[1].value->kind == ast::ExprKind::Number) {
      if (!binding && node.mod && node.mod->value)
        binding = lowerModValue(*node.mod);
      double k = dim->args[1].value->number;
      if (!binding || k < 1 || k > double(binding->shape.size()) ||
          k != std::floor(k) || binding->shape.size() != d.dims.size()) {
        report(DiagId::ErrArraySizeMissing, dim->loc, {d.name});
        node.state = InstNode::State::Failed;
        return;
      }
      node.dims.push_back(binding->shape[size_t(k) - 1]);
      continue;
    }
    // `Real x[E]` for an enumeration E: one element per literal.
    const ast::ClassDef *byEnum = enumerationNamed(*dim, declScope);
    std::optional<int64_t> n =
        byEnum ? std::optional<int64_t>(int64_t(byEnum->enumLiterals.size()))
               : evalInteger(*dim, declScope, nullptr,
                             "array size of '" + d.name + "'");
    if (!n) {
      node.state = InstNode::State::Failed;
      return;
    }
    node.dims.push_back(*n);
  }
  if (!resolveType(node)) {
    node.state = InstNode::State::Failed;
    return;
  }
  if (node.inExpandable)
    node.causality = ast::Causality::None;
  int64_t count = 1;
  for (int64_t n : node.dims) {
    if (n < 0) {
      report(DiagId::ErrNegativeArraySize, d.loc,
                    {d.name, std::to_string(n)});
      node.state = InstNode::State::Failed;
      return;
    }
    count = n == 0 ? 0 : count;
    if (count > 0 && n > kMaxArrayElements / count) {
      report(DiagId::ErrArrayTooLarge, d.loc,
                    {d.name, std::to_string(kMaxArrayElements)});
      node.state = InstNode::State::Failed;
      return;
    }
    count *= n;
  }
  // Instances of classes count, one per array element; leaves are bounded
  // by kMaxScalars instead.
  if (overBudget() || (!node.isLeaf() && !countInstances(count, node))) {
    node.state = InstNode::State::Failed;
    return;
  }

  if (node.isLeaf()) {
    checkModifiers(node);
    createLeafSlots(node);
    node.state = InstNode::State::Done;
    return;
  }

  // A class instance: a class containing itself is a cycle; a long chain
  // of distinct classes is not, but its depth is bounded because
  // elaboration recurses once per level.
  unsigned depth = 0;
  for (InstNode *a = node.parent; a; a = a->parent, ++depth) {
    if (a->cls == node.cls) {
      report(DiagId::ErrRecursiveComponent, d.loc, {d.name, node.typeName});
      node.state = InstNode::State::Failed;
      return;
    }
    if (depth >= kMaxInstanceDepth) {
      report(DiagId::ErrComponentTooDeep, d.loc,
             {d.name, node.typeName, std::to_string(kMaxInstanceDepth)});
      node.state = InstNode::State::Failed;
      return;
    }
  }

  // A record's value binds its fields (RecordBindings.cpp).
  if (node.mod && node.mod->value &&
      (node.cls->kind != ast::ClassKind::Record || node.isArray())) {
    report(DiagId::ErrUnsupported, node.mod->loc,
                  {"a value for a component of type '" + node.typeName + "'"});
    node.state = InstNode::State::Failed;
    return;
  }
  if (node.isArray()) {
    node.elements.reserve(count);
    for (int64_t i = 0; i < count; ++i) {
      auto elem = std::make_unique<InstNode>();
      std::vector<int64_t> subs = elementSubscripts(node.dims, i);
      elem->name = elementName(node.name, node.dims, i);
      elem->path = elementName(node.path, node.dims, i);
      elem->parent = node.parent;
      elem->decl = node.decl;
      elem->declClass = node.declClass;
      elem->mod = indexMod(node.mod, subs);
      elem->cls = node.cls;
      elem->typeName = node.typeName;
      elem->isConnector = node.isConnector;
      elem->flow = node.flow;
      elem->variability = node.variability;
      elem->causality = node.causality;
      elem->state = InstNode::State::Elaborating;
      prepareInstance(*elem);
      elem->state = InstNode::State::Prepared;
      node.elements.push_back(std::move(elem));
      if (overBudget())
        break;
    }
    // Every element exists: a member of one may name another.
    node.membersReady = true;
  } else {
    prepareInstance(node);
  }
  node.state = InstNode::State::Prepared;
  if (!membersOnly)
    finishPrepared(node);
}

namespace {
/// Walks a class and its bases, collecting members and equations into an
/// instance.
struct Collector {
  Flattener &f;
  ClassTable &classes;
  DiagnosticEngine &diags;
  InstNode &node;
  std::vector<const ast::ClassDef *> stack;
  std::vector<ModPtr> extendsMods; // innermost last
  std::vector<ModPtr> allExtendsMods;

  void collect(const ast::ClassDef &cls,
               ModPtr (Flattener::*makeMod)(const ast::Modification *,
                                            const Scope &)) {
    stack.push_back(&cls);
    for (const ast::Extends &ext : cls.extends) {
      const ast::ClassDef *base =
          classes.resolveClass(ext.base, &cls, cls.file);
      ModPtr extMod = (f.*makeMod)(ext.mod.get(), Scope{&node, &cls});
      // `extends R2` where `model R2 = Resistor(R = 2)`.
      for (unsigned guard = 0; base && base->isShort && guard < 32; ++guard) {
        ModPtr shortMod =
            (f.*makeMod)(base->shortMod.get(), Scope{nullptr, base->parent});
        extMod = mergeMods(extMod, shortMod);
        if (builtinNamed(base->shortBase) != BuiltinType::None) {
          f.report(DiagId::ErrUnsupported, ext.loc,
                       {"extending a built-in type"});
          base = nullptr;
          break;
        }
        base = classes.resolveClass(base->shortBase, base->parent, base->file);
      }
      if (!base)
        continue;
      if (std::find(stack.begin(), stack.end(), base) != stack.end()) {
        f.report(DiagId::ErrRecursiveExtends,
                     SourceRange{ext.base.loc, ext.base.length},
                     {base->name});
        continue;
      }
      if (stack.size() >= Flattener::kMaxInstanceDepth) {
        f.report(DiagId::ErrExtendsTooDeep,
                 SourceRange{ext.base.loc, ext.base.length},
                 {base->name, std::to_string(Flattener::kMaxInstanceDepth)});
        continue;
      }
      if (base->kind == ast::ClassKind::Function ||
          base->kind == ast::ClassKind::Package) {
        f.report(DiagId::ErrNotAType, ext.base.loc,
                     {base->name, ast::classKindName(base->kind)});
        continue;
      }
      allExtendsMods.push_back(extMod);
      extendsMods.push_back(extMod);
      collect(*base, makeMod);
      extendsMods.pop_back();
    }
    for (const auto &section : cls.modelAlgorithms)
      node.algorithms.emplace_back(&section, &cls);
    for (const auto &section : cls.initialAlgorithms)
      node.initialAlgorithms.emplace_back(&section, &cls);
    for (const ast::Component &comp : cls.components) {
      ModPtr mod = (f.*makeMod)(comp.mod.get(), Scope{&node, &cls});
      for (auto it = extendsMods.rbegin(); it != extendsMods.rend(); ++it)
        mod = mergeMods(*it ? (*it)->sub(comp.name) : nullptr, mod);
      if (const InstNode *existing = node.findMember(comp.name)) {
        const ast::Component *old = existing->decl;
        if (old != &comp && (old->typeName.str() != comp.typeName.str() ||
                             old->dims.size() != comp.dims.size())) {
          Diagnostic &diag =
              f.report(DiagId::ErrDuplicateDeclaration,
                           SourceRange{comp.loc, comp.length},
                           {comp.name, old->typeName.str(), comp.typeName.str()});
          DiagnosticEngine::addNote(diag, old->loc, DiagId::NoteDeclaredHere,
                                    {comp.name});
        }
        continue;
      }
      auto child = std::make_unique<InstNode>();
      child->name = comp.name;
      child->path = joinPath(node.path, comp.name);
      child->parent = &node;
      child->decl = &comp;
      child->declClass = &cls;
      child->mod = mod;
      node.addMember(std::move(child));
    }
    for (const ast::Equation &eq : cls.equations)
      node.equations.emplace_back(&eq, &cls);
    for (const ast::Equation &eq : cls.initialEquations)
      node.initialEquations.emplace_back(&eq, &cls);
    stack.pop_back();
  }
};
} // namespace

void Flattener::elaborateInstance(InstNode &node) {
  prepareInstance(node);
  elaborateMembers(node);
}

void Flattener::prepareInstance(InstNode &node) {
  Collector c{*this, classes_, diags_, node, {}, {}, {}};
  c.collect(*node.cls, &Flattener::makeMod);
  node.membersReady = true;
  if (node.cls->expandable) {
    expandables_.push_back(&node);
    for (auto &m : node.members)
      m->inExpandable = true;
  }
  // The outer modifier applies to the merged members.
  for (auto &m : node.members)
    m->mod = mergeMods(node.mod ? node.mod->sub(m->name) : nullptr, m->mod);
  if (node.mod && node.mod->value && !node.isArray())
    bindRecordValue(node);
  checkModifiers(node);
  // A member redeclared by a modifier (of an extends clause or of this
  // instance) takes its new declaration; the modifiers of its original one
  // still apply beneath the new ones (MLS 7.3.2).
  for (auto &m : node.members)
    if (m->mod && m->mod->redeclare) {
      m->decl = m->mod->redeclare;
      m->declClass = m->mod->redeclareScope.cls;
    }
  removeDisabledMembers(node);
  linkOuterMembers(node);
  for (const ModPtr &ext : c.allExtendsMods) {
    if (!ext)
      continue;
    for (auto &[name, sub] : ext->subs)
      // A removed conditional component takes its modifiers with it
      // (MLS 4.4.5: MSL's adaptors modify their optional pder2).
      if (!node.findMember(name) && !node.findRemoved(name)) {
        std::vector<std::string> names;
        for (const auto &m : node.members)
          names.push_back(m->name);
        std::string best = closestName(name, names);
        if (best.empty())
          report(DiagId::ErrUnknownModifier, SourceRange{sub->nameLoc, sub->nameLength},
                        {name, node.cls->name});
        else
          report(DiagId::ErrUnknownModifierSuggest,
                        SourceRange{sub->nameLoc, sub->nameLength}, {name, node.cls->name, best});
      }
  }
}

void Flattener::elaborateMembers(InstNode &node) {
  // An expandable connector's members are elaborated when a connect
  // names them (ExpandableConnectors.cpp).
  if (node.cls && node.cls->expandable)
    return;
  for (auto &m : node.members) {
    ensureElaborated(*m, m->decl->loc);
    if (m->innerHalf)
      ensureElaborated(*m->innerHalf, m->decl->loc);
    if (overBudget())
      break;
  }
}

void Flattener::linkOuterMembers(InstNode &node) {
  for (auto &m : node.members) {
    if (!m->decl->isOuter)
      continue;
    // The nearest enclosing instance (above the one declaring it) with an
    // `inner` component of that name.
    for (InstNode *p = node.parent; p && !m->inner; p = p->parent) {
      if (p->isArray())
        continue;
      for (const auto &c : p->members)
        if (c->name == m->name && c->decl && c->decl->isInner) {
          m->inner = c->innerHalf ? c->innerHalf.get() : c.get();
          break;
        }
    }
    // `inner outer` with no inner above: the inner of the components
    // below it, an ordinary component here.
    if (!m->inner && m->decl->isInner)
      continue;
    m->membersReady = true;
    if (!m->inner)
      m->inner = addedInner(*m);
    if (!m->inner) {
      // Failed: its uses say nothing more.
      m->state = InstNode::State::Failed;
    } else {
      m->state = InstNode::State::Done;
      ensureElaborated(*m->inner, m->decl->loc);
      if (m->decl->isInner) {
        auto half = std::make_unique<InstNode>();
        half->name = m->name;
        half->path = m->path;
        half->parent = &node;
        half->decl = m->decl;
        half->declClass = m->declClass;
        half->mod = m->mod;
        m->innerHalf = std::move(half);
      }
    }
  }
}

InstNode *Flattener::addedInner(const InstNode &m) {
  // "If there is one (or more identical) outer declarations with the same
  // name and no matching inner declaration, an inner element is
  // automatically added at the top of the model and a diagnostic is
  // given" (MLS 5.4): MSL's noise blocks find their GlobalSeed so, and a
  // StateGraph step its stateGraphRoot, checked on their own.
  SourceRange where{m.decl->loc, m.decl->length};
  uint32_t file = m.declClass ? m.declClass->file : m.decl->loc.file;
  const ast::ClassDef *cls =
      classes_.resolveClass(m.decl->typeName, m.declClass, file);
  std::string type = m.decl->typeName.str();
  auto it = addedInners_.find(m.name);
  if (it != addedInners_.end()) {
    if (it->second.cls == cls)
      return it->second.node.get();
    report(DiagId::ErrNoInner, where,
           {m.name, type, it->second.node->typeName});
    return nullptr;
  }
  if (!cls)
    return nullptr; // reported by the lookup
  report(DiagId::WarnInnerAdded, where, {m.name, type});
  auto added = std::make_unique<InstNode>();
  added->name = m.name;
  added->path = m.name;
  added->parent = root_.get();
  added->decl = m.decl;
  added->declClass = m.declClass;
  InstNode *node = added.get();
  addedInners_[m.name] = AddedInner{std::move(added), cls};
  return node;
}

void Flattener::removeDisabledMembers(InstNode &node) {
  // A conditional component's condition is a parameter expression of the
  // instance it is declared in (MLS 4.4.5); false removes it.
  bool any = false;
  for (const auto &m : node.members)
    any = any || m->decl->condition;
  if (!any)
    return;
  // Decided first, moved after: a condition reads other members.
  std::vector<bool> off;
  for (const auto &m : node.members) {
    const ast::Component &d = *m->decl;
    std::optional<double> on =
        d.condition ? evalConstant(*d.condition, Scope{&node, m->declClass},
                                   nullptr, "condition of a component")
                    : std::optional<double>(1.0);
    off.push_back(on && *on == 0.0);
  }
  std::vector<std::unique_ptr<InstNode>> kept;
  for (size_t k = 0; k < node.members.size(); ++k)
    (off[k] ? node.removed : kept).push_back(std::move(node.members[k]));
  node.members.clear();
  node.memberIndex.clear();
  for (auto &m : kept)
    node.addMember(std::move(m));
}

void Flattener::checkModifiers(InstNode &node) {
  if (!node.mod)
    return;
  std::vector<std::string> names;
  if (node.isLeaf())
    names = attributeNames(node.builtin);
  else
    for (const auto &m : node.members)
      names.push_back(m->name);
  std::string typeName =
      node.isLeaf() ? node.typeName : (node.cls ? node.cls->name : node.typeName);
  for (const auto &[name, sub] : node.mod->subs) {
    if (std::find(names.begin(), names.end(), name) != names.end())
      continue;
    std::string best = closestName(name, names);
    if (best.empty())
      report(DiagId::ErrUnknownModifier,
                    SourceRange{sub->nameLoc, sub->nameLength}, {name, typeName});
    else
      report(DiagId::ErrUnknownModifierSuggest,
                    SourceRange{sub->nameLoc, sub->nameLength}, {name, typeName, best});
  }
}

void Flattener::createLeafSlots(InstNode &node) {
  int64_t count = 1;
  for (int64_t n : node.dims)
    count *= n;
  if (node.builtin == BuiltinType::String)
    return; // strings only document; using one in an equation is an error
  if (node.isParameterLike() && !(node.mod && node.mod->value))
    adoptInitialEquation(node);
  // A parameter's value is where an impure function may be called.
  std::optional<ImpureContext> impure;
  if (node.variability == ast::Variability::Parameter)
    impure.emplace(*this);
  node.initialParameter = isInitialParameter(node);
  node.slots.reserve(count);
  for (int64_t i = 0; i < count; ++i) {
    ModPtr m = node.dims.empty()
                   ? node.mod
                   : indexMod(node.mod, elementSubscripts(node.dims, i));
    std::string name = elementName(node.path, node.dims, i);
    if (node.isParameterLike())
      createParameter(node, name, m);
    else
      createVariable(node, name, m);
  }
  if (!node.isParameterLike() && node.mod && node.mod->value)
    node.binding = node.mod;
  if (node.initialParameter)
    for (const Slot &slot : node.slots) {
      initialParameterVars_.insert(slot.id);
      // Constant in time: der(p) = 0, at the declaration.
      ir::Equation e;
      e.residual = ctx().var(slot.id, 1);
      e.loc = node.decl->loc;
      e.component = node.parent ? node.parent->path : "";
      e.origin = ir::EquationOrigin::Binding;
      e.text = "der(" + model_->variables[slot.id].name + ") = 0";
      model_->equations.push_back(std::move(e));
    }
}

bool Flattener::fixedFalse(const InstNode &node) {
  ModPtr fixed = node.mod ? node.mod->sub("fixed") : nullptr;
  if (!fixed || !fixed->value)
    return false;
  std::optional<Value> v = lowerModValue(*fixed);
  if (!v || v->isString || v->elems.size() != 1)
    return false;
  std::optional<double> c = constantValue(v->elems[0]);
  return c && *c == 0;
}

void Flattener::adoptInitialEquation(InstNode &node) {
  // An Integer or Boolean parameter with fixed = false cannot be an unknown
  // of the continuous initialization (a Real one is: isInitialParameter).
  // Its initial equation `p = expr` (MSL's Noise blocks: `localSeed =
  // automaticLocalSeed(getInstanceName())`) computes it from parameters,
  // which a binding does at the same instant: it becomes p's binding.
  if ((node.builtin != BuiltinType::Integer &&
       node.builtin != BuiltinType::Boolean) ||
      !node.dims.empty() || !node.parent ||
      node.variability != ast::Variability::Parameter || !fixedFalse(node))
    return;
  for (const auto &[eq, cls] : node.parent->initialEquations) {
    if (eq->kind != ast::EquationKind::Simple || !eq->lhs || !eq->rhs ||
        eq->lhs->kind != ast::ExprKind::Ref || eq->lhs->parts.size() != 1 ||
        eq->lhs->parts[0].name != node.name ||
        !eq->lhs->parts[0].subscripts.empty())
      continue;
    auto mod = std::make_shared<Mod>(node.mod ? *node.mod : Mod{});
    mod->value = eq->rhs.get();
    mod->text = eq->text;
    mod->loc = eq->rhs->loc;
    mod->length = eq->rhs->length;
    mod->scope = Scope{node.parent, cls};
    mod->index.clear();
    node.mod = mod;
    adoptedInitialEquations_.insert({node.parent, eq});
    return;
  }
}

bool Flattener::isInitialParameter(const InstNode &node) {
  if (node.variability != ast::Variability::Parameter ||
      node.builtin != BuiltinType::Real || !node.mod)
    return false;
  ModPtr fixed = node.mod->sub("fixed");
  if (!fixed || !fixed->value) {
    // A binding that reads parameters the initialization finds (MSL's
    // ContinuousMean: `actualStartTime = max(t_0, startTime)` with t_0
    // fixed = false) is found there too, as its initial equation.
    // Scalars only, and not literals: nothing else is lowered twice.
    if (!node.mod->value || !node.dims.empty() ||
        node.mod->value->kind == ast::ExprKind::Number ||
        node.decl->prefix.variability == ast::Variability::Constant)
      return false;
    std::optional<Value> v = lowerModValue(*node.mod);
    if (!v || v->isString || v->elems.empty())
      return false;
    bool reads = false;
    for (ir::ExprRef e : v->elems) {
      if (ir::dependsOnTime(e))
        return false;
      for (ir::VarKey k : ir::freeVariables(e)) {
        if (!initialParameterVars_.count(k.var))
          return false;
        reads = true;
      }
    }
    return reads;
  }
  return fixedFalse(node);
}

namespace {
/// A scalar number out of a modifier value, with the errors for strings
/// and arrays. With `binding`, the value is a binding an emitted program may
/// re-evaluate: `*binding` gets its expression when it reads parameters.
/// Without, the parameters it reads become structural.
std::optional<double> scalarNumber(Flattener &f, const Mod &mod,
                                   const std::string &what,
                                   ir::ExprRef *binding = nullptr) {
  std::optional<Value> v = f.lowerModValue(mod);
  if (!v)
    return std::nullopt;
  if (v->isString) {
    f.report(DiagId::ErrModifierType, SourceRange{mod.loc, mod.length},
                     {what, "a number", "a string"});
    return std::nullopt;
  }
  if (!v->shape.empty()) {
    f.report(DiagId::ErrModifierType, SourceRange{mod.loc, mod.length},
                     {what, "a scalar", describeShape(v->shape)});
    return std::nullopt;
  }
  ir::ExprRef e = v->scalarExpr();
  // A parameter whose own value failed has had its error: whatever is
  // computed from it would only repeat it (division by zero with its 0).
  if (f.readsFailedParameter(e))
    return std::nullopt;
  std::string evalError;
  std::optional<double> c =
      binding ? f.bindingValue(e, &evalError) : f.constantValue(e, &evalError);
  if (!c) {
    if (evalError.empty())
      f.report(DiagId::ErrNotConstant, SourceRange{mod.loc, mod.length},
               {what});
    else
      f.report(DiagId::ErrValueNotANumber, SourceRange{mod.loc, mod.length},
               {what, evalError});
    return c;
  }
  if (!std::isfinite(*c)) {
    // 0/0 or an overflow: every use downstream would be nan too.
    f.report(DiagId::ErrNotFinite, SourceRange{mod.loc, mod.length},
             {what, fmtInteger(*c)});
    return std::nullopt;
  }
  if (binding && !e->isConstant())
    *binding = e;
  return c;
}
} // namespace

std::string Flattener::readUnit(const ModPtr &mod, const std::string &name) {
  ModPtr u = mod ? mod->sub("unit") : nullptr;
  if (!u || !u->value)
    return "";
  std::optional<Value> uv = lowerModValue(*u);
  if (uv && !uv->isString) {
    report(DiagId::ErrModifierType, SourceRange{u->loc, u->length},
           {"attribute 'unit' of '" + name + "'", "a string", "a number"});
    return "";
  }
  return uv ? uv->str : "";
}

void Flattener::createParameter(InstNode &node, const std::string &name,
                                const ModPtr &mod) {
  ir::Parameter p;
  p.name = name;
  p.component = node.parent ? node.parent->path : "";
  p.loc = node.decl->loc;
  p.unit = readUnit(mod, name);
  p.description = node.decl->description;
  p.isConstant = node.variability == ast::Variability::Constant;
  p.isInteger = node.builtin == BuiltinType::Integer;
  p.isBoolean = node.builtin == BuiltinType::Boolean;
  p.externalObject = node.externalObject;
  std::string what = "value of '" + name + "'";
  bool haveValue = false;
  if (mod && mod->value) {
    if (std::optional<double> v =
            scalarNumber(*this, *mod, what, &p.binding)) {
      p.value = *v;
      haveValue = true;
    }
  } else if (ModPtr start = mod ? mod->sub("start") : nullptr;
             start && start->value) {
    if (std::optional<double> v =
            scalarNumber(*this, *start, what, &p.binding))
      p.value = *v;
    haveValue = true;
  }
  auto ov = overrides_.find(name);
  if (ov != overrides_.end()) {
    ov->second.second = true;
    if (p.isConstant)
      report(DiagId::ErrOverrideConstant, p.loc, {name});
    else {
      p.value = ov->second.first;
      p.binding = nullptr;
      haveValue = true;
    }
  }
  if (!haveValue && !(mod && mod->value))
    report(DiagId::WarnParameterNoValue, p.loc, {name});
  if (p.isInteger && p.value != std::floor(p.value))
    report(DiagId::ErrModifierType, p.loc,
                  {what, "an Integer", fmtInteger(p.value)});
  bool failed = !haveValue && mod && mod->value;
  ir::ParamId id = model_->addParameter(std::move(p));
  if (failed)
    failedParameters_.insert(id);
  node.slots.push_back({true, id});
}

void Flattener::createVariable(InstNode &node, const std::string &name,
                               const ModPtr &mod) {
  ir::Variable v;
  v.name = name;
  v.component = node.parent ? node.parent->path : "";
  v.loc = node.decl->loc;
  v.isInput = node.causality == ast::Causality::Input;
  v.isOutput = node.causality == ast::Causality::Output;
  v.isInteger = node.builtin == BuiltinType::Integer;
  v.isBoolean = node.builtin == BuiltinType::Boolean;
  v.isDiscrete = v.isInteger || v.isBoolean ||
                 node.variability == ast::Variability::Discrete;
  ir::Equation startEquation; // its residual: the start's value, if any
  if (mod) {
    auto attr = [&](const char *key,
                    ir::ExprRef *binding = nullptr) -> std::optional<double> {
      ModPtr a = mod->sub(key);
      if (!a || !a->value)
        return std::nullopt;
      return scalarNumber(*this, *a,
                          std::string("attribute '") + key + "' of '" + name + "'",
                          binding);
    };
    if (auto s = attr("fixed"))
      v.fixed = *s != 0;
    ModPtr start = mod->sub("start");
    std::optional<Value> sv;
    if (start && start->value)
      sv = lowerModValue(*start); // reports what does not lower
    if (sv && !sv->isString && sv->elems.size() == 1 &&
        !ir::freeVariables(sv->elems[0]).empty()) {
      // `x(start = p, fixed = true)` with p a parameter the initialization
      // finds (fixed = false): the initial equation x = p; without fixed,
      // a guess from p's start (OpenModelica's startValue1..3).
      if (v.fixed) {
        startEquation.residual = sv->elems[0];
        startEquation.loc = start->loc;
        startEquation.origin = ir::EquationOrigin::Initial;
        startEquation.text = name + " = " + start->text;
      } else {
        v.startGuess = sv->elems[0];
      }
      v.fixed = false;
    } else if (sv) {
      if (auto s = attr("start", &v.startBinding)) {
        v.start = *s;
        v.hasStart = true;
      }
    }
    if (auto s = attr("nominal"))
      v.nominal = *s;
    if (auto s = attr("min"))
      v.min = *s;
    if (auto s = attr("max"))
      v.max = *s;
    if (auto s = attr("stateSelect"))
      v.stateSelect = static_cast<ir::StateSelect>(
          std::clamp(static_cast<int>(*s), 0, 4));
  }
  // --override x.start=value: replaces the start value as written, and
  // whatever it was bound to (a fixed start stays fixed).
  if (auto ov = overrides_.find(name + kStartSuffix); ov != overrides_.end()) {
    ov->second.second = true;
    v.start = ov->second.first;
    v.hasStart = true;
    v.startBinding = nullptr;
  }
  v.unit = readUnit(mod, name);
  v.description = node.decl->description;
  bool isFlow = node.flow && (node.isConnector ||
                              (node.parent && node.parent->isConnector));
  ir::VarId id = model_->addVariable(std::move(v));
  node.slots.push_back({false, id});
  if (startEquation.residual) {
    startEquation.residual = ctx().sub(ctx().var(id), startEquation.residual);
    startEquation.component = node.parent ? node.parent->path : "";
    model_->initialEquations.push_back(std::move(startEquation));
  }
  if (isFlow)
    flowVars_.push_back(id);
}

namespace {
/// The string value of annotation field `key` among `args`, if any.
const ast::Expr *annotationString(const std::vector<ast::Modifier> &args,
                                  const std::string &key) {
  for (const ast::Modifier &a : args)
    if (a.path.size() == 1 && a.path[0] == key && a.mod && a.mod->value &&
        a.mod->value->kind == ast::ExprKind::String)
      return a.mod->value.get();
  return nullptr;
}
} // namespace

void Flattener::checkUsedVersions(const ast::ClassDef &cls) {
  // `annotation(uses(Modelica(version = "4.1.0")))` on the model or a
  // package around it (MLS 18.8.2), against the `version` annotation of
  // the library found on the path: a different one is a warning.
  for (const ast::ClassDef *c = &cls; c; c = c->parent)
    for (const auto &ann : c->annotations)
      for (const ast::Modifier &uses : ann->args) {
        if (uses.path.size() != 1 || uses.path[0] != "uses" || !uses.mod)
          continue;
        for (const ast::Modifier &lib : uses.mod->args) {
          const ast::Expr *wanted =
              lib.mod && lib.path.size() == 1
                  ? annotationString(lib.mod->args, "version")
                  : nullptr;
          if (!wanted)
            continue;
          LexicalHit hit = classes_.lookup(lib.path[0], nullptr, c->file);
          if (!hit.cls)
            continue; // reported where the library is used
          const ast::Expr *found = nullptr;
          for (const auto &libAnn : hit.cls->annotations)
            if (!found)
              found = annotationString(libAnn->args, "version");
          if (found && found->text != wanted->text)
            report(DiagId::WarnUsesVersion,
                   SourceRange{wanted->loc, wanted->length},
                   {c->name, lib.path[0], wanted->text, found->text});
        }
      }
}

void Flattener::readExperiment(const ast::ClassDef &cls, InstNode &root) {
  struct Field {
    std::optional<double> *slot;
    SourceRange where;
  };
  std::map<std::string, Field> seen;
  for (const auto &ann : cls.annotations)
    for (const ast::Modifier &arg : ann->args) {
      if (arg.path.size() != 1 || arg.path[0] != "experiment" || !arg.mod)
        continue;
      for (const ast::Modifier &field : arg.mod->args) {
        if (field.path.size() != 1 || !field.mod || !field.mod->value)
          continue;
        const std::string &key = field.path[0];
        std::optional<double> *slot =
            key == "StartTime"   ? &model_->experiment.startTime
            : key == "StopTime"  ? &model_->experiment.stopTime
            : key == "Tolerance" ? &model_->experiment.tolerance
            : key == "Interval"  ? &model_->experiment.interval
                                 : nullptr;
        if (!slot)
          continue;
        const ast::Expr &value = *field.mod->value;
        SourceRange where{value.loc, value.length};
        std::optional<double> v = evalConstant(value, Scope{&root, &cls},
                                               nullptr, "experiment " + key);
        if (!v)
          continue;
        // The runtime trusts these values; a bad one is the model's error,
        // reported where it is written (evalConstant rejects non-finite).
        if ((key == "Tolerance" || key == "Interval") && *v <= 0) {
          report(DiagId::ErrExperimentNotPositive, where,
                 {key, fmtInteger(*v)});
          continue;
        }
        *slot = *v;
        seen[key] = Field{slot, where};
      }
    }
  auto start = seen.find("StartTime"), stop = seen.find("StopTime");
  double startTime = start != seen.end() ? **start->second.slot : 0.0;
  if (stop != seen.end() && **stop->second.slot < startTime) {
    report(DiagId::ErrExperimentStopBeforeStart, stop->second.where,
           {fmtInteger(**stop->second.slot), fmtInteger(startTime)});
    model_->experiment.stopTime.reset();
  }
}

} // namespace ldae::frontend
