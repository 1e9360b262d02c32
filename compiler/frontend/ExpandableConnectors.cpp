// Expandable connectors (MLS 9.1.3), as MSL's signal buses use them:
//   expandable connector ControlBus  Real realSignal1; ... end ControlBus;
//   connect(sine.y, controlBus.realSignal1);
//   connect(integerStep.y, controlBus.integerSignal);  // not declared: added
// A member declared in an expandable connector is only potentially present;
// it is present when a connect names it. A connect may name a member the
// connector does not declare: it is added with the type of the other side.
// Expandable connectors connected to each other hold the union of their
// members, nested ones too. Before the connect equations are collected,
// one sweep over them (collectConnects with expandSweep_) adds and marks
// members, the unions are taken to a fixed point, and the members never
// present are removed, so they are no variables of the model.
// Members of an expandable connector have no input/output prefix of their
// own here (the spec derives it from the connections; no equation depends
// on it) and may be connected though their type is no connector.
#include "frontend/Flattener.h"

#include <algorithm>
#include <map>

namespace ldae::frontend {

namespace {

bool isExpandable(const InstNode &n) {
  return n.cls && n.cls->expandable && !n.isArray();
}

/// A member whose declaration was never elaborated is not present.
bool isPresent(const InstNode &m) {
  return m.state != InstNode::State::Declared;
}

} // namespace

std::pair<InstNode *, std::string>
Flattener::missingExpandableMember(const ast::Expr &ref, const Scope &scope) {
  if (ref.global || ref.parts.size() < 2 || !scope.inst)
    return {nullptr, ""};
  InstNode *n = scope.inst;
  for (size_t i = 0; i + 1 < ref.parts.size(); ++i) {
    const ast::RefPart &part = ref.parts[i];
    if (!part.subscripts.empty() || n->isLeaf())
      return {nullptr, ""};
    n = n->findMember(part.name);
    if (!n || !ensureMembers(*n, ref.loc) || n->isArray())
      return {nullptr, ""};
  }
  const ast::RefPart &last = ref.parts.back();
  if (!isExpandable(*n) || !last.subscripts.empty() ||
      n->findMember(last.name) || n->findRemoved(last.name))
    return {nullptr, ""};
  return {n, last.name};
}

InstNode *Flattener::addExpandableMember(InstNode &bus,
                                         const std::string &name,
                                         const InstNode &like,
                                         const std::vector<int64_t> &dims) {
  auto decl = std::make_unique<ast::Component>();
  decl->name = name;
  decl->loc = like.decl->loc;
  decl->length = like.decl->length;
  decl->text = name;
  decl->typeName = like.decl->typeName;
  decl->description = like.decl->description;
  // Sizes as numbers: the other side's size expressions mean something
  // only where that side is declared.
  for (int64_t d : dims) {
    auto e = std::make_unique<ast::Expr>();
    e->kind = ast::ExprKind::Number;
    e->number = static_cast<double>(d);
    e->loc = like.decl->loc;
    decl->dims.push_back(std::move(e));
  }
  auto m = std::make_unique<InstNode>();
  m->name = name;
  m->path = bus.path.empty() ? name : bus.path + "." + name;
  m->parent = &bus;
  m->decl = decl.get();
  m->declClass = like.declClass;
  m->inExpandable = true;
  InstNode *added = m.get();
  bus.addMember(std::move(m));
  addedBusMembers_.push_back(std::move(decl));
  return added;
}

void Flattener::augmentConnect(const ast::Equation &eq, const Scope &scope,
                               Env *env) {
  if (namesRemoved(*eq.lhs, scope) || namesRemoved(*eq.rhs, scope))
    return;
  auto [busA, nameA] = missingExpandableMember(*eq.lhs, scope);
  auto [busB, nameB] = missingExpandableMember(*eq.rhs, scope);
  // Neither side declares it: the main sweep reports the missing member.
  if (busA && busB)
    return;
  if (busA || busB) {
    const ast::Expr &other = busA ? *eq.rhs : *eq.lhs;
    std::optional<Selection> sel = selectComponents(other, scope, env);
    if (!sel || sel->targets.empty())
      return;
    InstNode &like = *sel->targets[0].node;
    std::vector<int64_t> dims = sel->shape;
    // A scalar taken out of an array leaf is one element of its type.
    if (sel->targets[0].slot >= 0 && sel->shape.empty())
      dims.clear();
    addExpandableMember(busA ? *busA : *busB, busA ? nameA : nameB, like,
                        dims);
  }
  // Both sides resolve now; naming a declared member makes it present.
  std::optional<Selection> a = selectComponents(*eq.lhs, scope, env);
  std::optional<Selection> b = selectComponents(*eq.rhs, scope, env);
  if (!a || !b || a->targets.size() != b->targets.size())
    return;
  for (size_t i = 0; i < a->targets.size(); ++i) {
    InstNode *na = a->targets[i].node, *nb = b->targets[i].node;
    if (a->targets[i].slot < 0 && b->targets[i].slot < 0 && isExpandable(*na) &&
        isExpandable(*nb))
      busPairs_.emplace_back(na, nb);
  }
}

void Flattener::completeExpandableConnectors() {
  // Connected expandable connectors hold the union of their members; the
  // members that are expandable themselves are connected in turn, so the
  // unions are repeated until nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    std::map<InstNode *, InstNode *> parent;
    std::vector<InstNode *> order;
    auto find = [&](InstNode *x) {
      if (!parent.count(x)) {
        parent[x] = x;
        order.push_back(x);
      }
      while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
      return x;
    };
    for (auto [a, b] : busPairs_) {
      InstNode *ra = find(a), *rb = find(b);
      if (ra != rb)
        parent[rb] = ra;
    }
    std::map<InstNode *, std::vector<InstNode *>> groups;
    for (InstNode *x : order)
      groups[find(x)].push_back(x);
    for (auto &[root, group] : groups) {
      // Names in order of first appearance, each with a present member
      // giving its type.
      std::vector<std::pair<std::string, InstNode *>> names;
      for (InstNode *bus : group)
        for (const auto &m : bus->members)
          if (isPresent(*m) &&
              std::none_of(names.begin(), names.end(),
                           [&](const auto &p) { return p.first == m->name; }))
            names.emplace_back(m->name, m.get());
      for (const auto &[name, like] : names) {
        InstNode *first = nullptr;
        for (InstNode *bus : group) {
          InstNode *m = bus->findMember(name);
          if (!m)
            m = addExpandableMember(*bus, name, *like, like->dims);
          if (!isPresent(*m))
            changed = true;
          if (!ensureElaborated(*m, like->decl->loc))
            continue;
          if (isExpandable(*m)) {
            if (first && std::find(busPairs_.begin(), busPairs_.end(),
                                   std::pair{first, m}) == busPairs_.end()) {
              busPairs_.emplace_back(first, m);
              changed = true;
            }
            first = first ? first : m;
          }
        }
      }
    }
  }
  // Never named, never present: removed with the variables they would be.
  for (InstNode *bus : expandables_) {
    std::vector<std::unique_ptr<InstNode>> kept;
    for (auto &m : bus->members) {
      if (m->state == InstNode::State::Prepared)
        ensureElaborated(*m, m->decl->loc);
      (isPresent(*m) ? kept : bus->removed).push_back(std::move(m));
    }
    bus->members.clear();
    bus->memberIndex.clear();
    for (auto &m : kept)
      bus->addMember(std::move(m));
  }
}

} // namespace ldae::frontend
