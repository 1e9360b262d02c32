// The discrete/continuous classification of Discrete.h.
#include "ir/Discrete.h"

#include "ir/Query.h"
#include "Traverse.h"

namespace ldae::ir {

std::vector<bool> discreteVariables(const Model &m) {
  std::vector<bool> d(m.variables.size(), false);
  for (VarId v = 0; v < m.variables.size(); ++v)
    d[v] = m.variables[v].isDiscrete;
  for (const WhenClause &w : m.whenClauses)
    for (ExprRef t : w.targets)
      d[t->var()] = true;
  return d;
}

bool isEventRelation(ExprRef e, const std::vector<bool> &discrete) {
  if (e->kind() != ExprKind::Compare || e->noEvent())
    return false;
  if (dependsOnTime(e))
    return true;
  for (VarKey k : freeVariables(e))
    if (k.var >= discrete.size() || !discrete[k.var])
      return true;
  return false;
}

bool isStepFunction(ExprRef e) {
  return e->kind() == ExprKind::Call &&
         (e->func() == FuncKind::Floor || e->func() == FuncKind::Ceil);
}

bool readsContinuous(ExprRef e, const std::vector<bool> &discrete) {
  bool found = false;
  ExprRef roots[] = {e};
  postOrder(
      roots,
      [&](ExprRef n) {
        return found || isEventRelation(n, discrete) || isStepFunction(n);
      },
      [&](ExprRef n) {
        if (n->kind() == ExprKind::Variable &&
            (n->var() >= discrete.size() || !discrete[n->var()]))
          found = true;
      });
  return found;
}

bool isDiscreteEquation(ExprRef residual, const std::vector<bool> &discrete) {
  if (readsContinuous(residual, discrete))
    return false;
  for (VarKey k : freeVariables(residual))
    if (k.var < discrete.size() && discrete[k.var])
      return true;
  return false;
}

} // namespace ldae::ir
