// connect(a, b) -> equations. Each connect pairs the scalar variables of two
// connectors of the same structure; the pairs form connection sets:
// potentials are equal (one equation per merge, so a set of n variables
// gives n - 1), flows sum to zero with inside connectors counted positive
// and outside ones (the enclosing model's own connectors) negative, and a
// flow variable never connected from the inside is zero.
#include "frontend/Flattener.h"

#include <numeric>

namespace ldae::frontend {
namespace {

/// Union-find with path halving over dense integer keys (0 <= key < size).
struct UnionFind {
  std::vector<uint64_t> parent;
  explicit UnionFind(size_t size) : parent(size) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  uint64_t find(uint64_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  bool unite(uint64_t a, uint64_t b) {
    a = find(a);
    b = find(b);
    if (a == b)
      return false;
    parent[b] = a;
    return true;
  }
};

std::string targetName(const RefTarget &t) {
  if (t.slot < 0)
    return t.node->path;
  return elementName(t.node->path, t.node->dims, t.slot);
}

} // namespace

bool Flattener::namesRemoved(const ast::Expr &ref, const Scope &scope) {
  InstNode *n = ref.global ? nullptr : scope.inst;
  for (const ast::RefPart &part : ref.parts) {
    if (!n || n->isLeaf())
      return false;
    if (n->findRemoved(part.name))
      return true;
    n = n->findMember(part.name);
    if (!n || !ensureElaborated(*n, ref.loc))
      return false;
    // An array of components: its elements share their conditional members.
    if (n->isArray())
      n = n->elements.empty() ? nullptr : n->elements.front().get();
  }
  return false;
}

void Flattener::addConnect(const ast::Equation &eq, const Scope &scope,
                           Env *env) {
  // A connect equation that names a removed conditional component is
  // removed with it (MLS 4.4.5).
  if (expandSweep_) {
    augmentConnect(eq, scope, env);
    return;
  }
  if (namesRemoved(*eq.lhs, scope) || namesRemoved(*eq.rhs, scope))
    return;
  std::optional<Selection> a = selectComponents(*eq.lhs, scope, env);
  std::optional<Selection> b = selectComponents(*eq.rhs, scope, env);
  if (!a || !b)
    return;
  if (a->shape != b->shape || a->targets.size() != b->targets.size()) {
    report(DiagId::ErrConnectSize, SourceRange{eq.loc, eq.length},
           {describeShape(a->shape), describeShape(b->shape)});
    return;
  }
  // `connect(p, r.p)` inside a model: `p` is the model's own connector,
  // seen from the outside of the connection set, and so is everything
  // inside it (MLS 9.1.2): Polyphase's `connect(sineVoltage.n, plug_n.pin)`
  // names the pins of the model's own plug. Counted as inside, the plug's
  // pins joined the set of the enclosing model's connect into one flow
  // sum, an equation short per pin.
  auto isOutside = [&](const ast::Expr &ref) {
    if (ref.parts.size() == 1)
      return true;
    InstNode *first = ref.global || !scope.inst
                          ? nullptr
                          : scope.inst->findMember(ref.parts.front().name);
    if (first && first->isArray())
      first = first->elements.empty() ? nullptr : first->elements.front().get();
    return first && first->isConnector;
  };
  bool aOutside = isOutside(*eq.lhs);
  bool bOutside = isOutside(*eq.rhs);
  for (size_t i = 0; i < a->targets.size(); ++i) {
    for (const auto &[t, ref] : {std::pair{a->targets[i], eq.lhs.get()},
                                 std::pair{b->targets[i], eq.rhs.get()}})
      if (!t.node->isConnector && !t.node->inExpandable) {
        report(DiagId::ErrNotAConnector, SourceRange{ref->loc, ref->length},
               {targetName(t), t.node->typeName});
        return;
      }
    if (!pairConnectors(a->targets[i], b->targets[i], eq, scope, aOutside,
                        bOutside)) {
      report(DiagId::ErrConnectIncompatible, SourceRange{eq.loc, eq.length},
             {targetName(a->targets[i]), a->targets[i].node->typeName,
              targetName(b->targets[i]), b->targets[i].node->typeName});
      return;
    }
    ++connectCount_[a->targets[i].node];
    ++connectCount_[b->targets[i].node];
  }
}

bool Flattener::pairConnectors(const RefTarget &a, const RefTarget &b,
                               const ast::Equation &eq, const Scope &scope,
                               bool aOutside, bool bOutside) {
  InstNode *na = a.node, *nb = b.node;
  if ((a.slot >= 0) != (b.slot >= 0))
    return false;
  if (a.slot >= 0) {
    if (na->builtin != nb->builtin || na->flow != nb->flow)
      return false;
    const Slot &sa = na->slots[a.slot], &sb = nb->slots[b.slot];
    if (sa.isParam || sb.isParam)
      return sa.isParam == sb.isParam; // parameters are not connected
    ConnectPair p;
    p.a = sa.id;
    p.b = sb.id;
    p.flow = na->flow;
    p.aOutside = aOutside;
    p.bOutside = bOutside;
    p.loc = eq.loc;
    p.text = eq.text;
    p.component = scope.inst ? scope.inst->path : "";
    connectPairs_.push_back(std::move(p));
    return true;
  }
  if (na->members.size() != nb->members.size())
    return false;
  for (auto &ma : na->members) {
    InstNode *mb = nb->findMember(ma->name);
    if (!mb)
      return false;
    if (ma->state != InstNode::State::Done || mb->state != InstNode::State::Done)
      return false;
    if (ma->dims != mb->dims || ma->isLeaf() != mb->isLeaf())
      return false;
    if (ma->isLeaf()) {
      if (ma->slots.size() != mb->slots.size())
        return false;
      for (size_t i = 0; i < ma->slots.size(); ++i)
        if (!pairConnectors({ma.get(), static_cast<int64_t>(i)},
                            {mb, static_cast<int64_t>(i)}, eq, scope, aOutside,
                            bOutside))
          return false;
    } else if (ma->isArray()) {
      for (size_t i = 0; i < ma->elements.size(); ++i)
        if (!pairConnectors({ma->elements[i].get(), -1},
                            {mb->elements[i].get(), -1}, eq, scope, aOutside,
                            bOutside))
          return false;
    } else if (!pairConnectors({ma.get(), -1}, {mb, -1}, eq, scope, aOutside,
                               bOutside)) {
      return false;
    }
  }
  return true;
}

void Flattener::buildConnectionEquations() {
  ir::ExprContext &c = ctx();
  // Tables by variable (potentials) and by flow key (variable, outside):
  // every key is below twice the number of variables.
  const size_t nv = model_->variables.size();
  UnionFind potentials(nv), flows(2 * nv);
  auto key = [](ir::VarId v, bool outside) {
    return (static_cast<uint64_t>(v) << 1) | (outside ? 1 : 0);
  };
  std::vector<bool> insideConnected(nv, false);
  std::vector<uint64_t> flowOrder; // keys in order of first appearance
  constexpr size_t kNone = SIZE_MAX;
  std::vector<size_t> firstPair(2 * nv, kNone);
  for (size_t i = 0; i < connectPairs_.size(); ++i) {
    const ConnectPair &p = connectPairs_[i];
    if (!p.flow) {
      if (potentials.unite(p.a, p.b)) {
        ir::Equation e;
        e.residual = c.sub(c.var(p.a), c.var(p.b));
        e.loc = p.loc;
        e.component = p.component;
        e.origin = ir::EquationOrigin::Connection;
        e.text = p.text;
        model_->equations.push_back(std::move(e));
      }
      continue;
    }
    for (auto [v, outside] : {std::pair{p.a, p.aOutside}, std::pair{p.b, p.bOutside}}) {
      uint64_t k = key(v, outside);
      if (firstPair[k] == kNone) {
        firstPair[k] = i;
        flowOrder.push_back(k);
      }
      if (!outside)
        insideConnected[v] = true;
    }
    flows.unite(key(p.a, p.aOutside), key(p.b, p.bOutside));
  }
  // One sum per flow set, at the connect that started it.
  // Members grouped by set, each in order of first appearance: a set's
  // index is the order in which its first member appeared.
  std::vector<size_t> setOf(2 * nv, kNone);
  std::vector<std::vector<uint64_t>> members;
  for (uint64_t k : flowOrder) {
    uint64_t r = flows.find(k);
    if (setOf[r] == kNone) {
      setOf[r] = members.size();
      members.emplace_back();
    }
    members[setOf[r]].push_back(k);
  }
  for (const std::vector<uint64_t> &m : members) {
    std::vector<ir::ExprRef> terms;
    size_t first = connectPairs_.size();
    for (uint64_t k : m) {
      ir::ExprRef v = c.var(static_cast<ir::VarId>(k >> 1));
      terms.push_back((k & 1) ? c.neg(v) : v);
      first = std::min(first, firstPair[k]);
    }
    const ConnectPair &p = connectPairs_[first];
    ir::Equation e;
    e.residual = c.add(terms);
    e.loc = p.loc;
    e.component = p.component;
    e.origin = ir::EquationOrigin::FlowSum;
    e.text = p.text;
    model_->equations.push_back(std::move(e));
  }
  for (ir::VarId v : flowVars_) {
    if (insideConnected[v])
      continue;
    const ir::Variable &var = model_->variables[v];
    ir::Equation e;
    e.residual = c.var(v);
    e.loc = var.loc;
    e.component = var.component;
    e.origin = ir::EquationOrigin::UnconnectedFlow;
    e.text = var.name + " = 0";
    model_->equations.push_back(std::move(e));
  }
}

} // namespace ldae::frontend
