// cardinality(c) (MLS 3.7.2.3): how many connect equations name connector
// c, from inside and outside its component. MSL's StateGraph asks it in
// if-equations of the component (`if cardinality(inPort[i]) == 0 then
// inPort[i].set = false`) whose connects are written in the model around
// it, which is flattened after its components. So the connect equations
// of the whole instance tree go in first, in a sweep of their own, and the
// count is a constant by the time any other equation reads it.
#include "frontend/Flattener.h"

namespace ldae::frontend {

bool containsConnect(const ast::Equation &eq) {
  if (eq.kind == ast::EquationKind::Connect)
    return true;
  if (eq.kind != ast::EquationKind::For && eq.kind != ast::EquationKind::If)
    return false;
  for (const auto &branch : eq.branches)
    for (const ast::Equation &e : branch)
      if (containsConnect(e))
        return true;
  return false;
}

void Flattener::collectConnects(InstNode &node) {
  if (node.state != InstNode::State::Done || node.inner || node.isLeaf() ||
      overBudget())
    return;
  if (node.isArray()) {
    for (auto &e : node.elements)
      collectConnects(*e);
    return;
  }
  for (auto &m : node.members) {
    collectConnects(*m);
    if (m->innerHalf)
      collectConnects(*m->innerHalf);
  }
  InstanceContext context(*this, &node);
  std::vector<ir::Equation> none;
  for (const auto &[eq, cls] : node.equations) {
    EqSink sink;
    sink.out = &none;
    flattenEquation(*eq, Scope{&node, cls}, nullptr, sink);
  }
}

std::optional<Value> Flattener::lowerCardinality(const ast::Expr &call,
                                                 const Scope &scope,
                                                 Env *env) {
  SourceRange where{call.loc, call.length};
  if (call.args.size() != 1 || !call.args[0].name.empty()) {
    report(DiagId::ErrCallArgCount, where,
           {"cardinality", "1", std::to_string(call.args.size())});
    return std::nullopt;
  }
  // Declarations are elaborated before any connect is known: a count
  // there would be 0 whatever the model says.
  if (connectSweep_ || !connectsCollected_) {
    report(DiagId::ErrUnsupported, where,
           {connectSweep_ ? "cardinality() in the condition of connect "
                            "equations"
                          : "cardinality() outside equations"});
    return std::nullopt;
  }
  const ast::Expr &ref = *call.args[0].value;
  if (ref.kind != ast::ExprKind::Ref) {
    report(DiagId::ErrNotAConnector, SourceRange{ref.loc, ref.length},
           {"argument of 'cardinality'", "an expression"});
    return std::nullopt;
  }
  std::optional<Selection> sel = selectComponents(ref, scope, env);
  if (!sel)
    return std::nullopt;
  if (sel->targets.size() != 1 || sel->targets[0].slot >= 0 ||
      !sel->targets[0].node->isConnector) {
    report(DiagId::ErrNotAConnector, SourceRange{ref.loc, ref.length},
           {ref.refName(), sel->targets.size() == 1
                               ? sel->targets[0].node->typeName
                               : describeShape(sel->shape)});
    return std::nullopt;
  }
  auto count = connectCount_.find(sel->targets[0].node);
  int n = count == connectCount_.end() ? 0 : count->second;
  return Value::scalar(ctx().constant(static_cast<double>(n)));
}

} // namespace ldae::frontend
