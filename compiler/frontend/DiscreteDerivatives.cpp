// der() of a discrete variable: Modelica's der needs a continuous
// argument, and a discrete one (piecewise constant, jumping at events) has
// none. Left to the passes it reached code generation as an unknown that
// no system has ("'der(k)' is neither an unknown nor the derivative of a
// differential unknown"), with no place in the source.
#include "frontend/Frontend.h"

#include "ir/Discrete.h"
#include "ir/Query.h"

namespace ldae::frontend {
namespace {

/// Why `v` is discrete, completing "'k' ...".
std::string discreteReason(const ir::Variable &v) {
  if (v.isInteger)
    return "is an Integer";
  if (v.isBoolean)
    return "is a Boolean";
  if (v.input != ir::EventInput::None)
    return "is an event input";
  if (v.isDiscrete)
    return "is declared discrete";
  return "is assigned in a when-clause";
}

} // namespace

bool checkDiscreteDerivatives(const ir::Model &model,
                              DiagnosticEngine &diags) {
  const std::vector<bool> discrete = ir::discreteVariables(model);
  bool ok = true;
  auto check = [&](ir::ExprRef e, SourceLoc loc) {
    if (!e)
      return;
    for (ir::VarKey k : ir::freeVariables(e)) {
      if (k.order == 0 || k.var >= discrete.size() || !discrete[k.var])
        continue;
      const ir::Variable &v = model.variables[k.var];
      Diagnostic &d = diags.report(DiagId::ErrDerOfDiscrete, loc,
                                   {v.name, discreteReason(v)});
      DiagnosticEngine::addNote(d, v.loc, DiagId::NoteDeclaredHere, {v.name});
      ok = false;
      return; // one per equation
    }
  };
  for (const ir::Equation &eq : model.equations)
    check(eq.residual, eq.loc);
  for (const ir::Equation &eq : model.initialEquations)
    check(eq.residual, eq.loc);
  for (const ir::WhenClause &w : model.whenClauses) {
    check(w.condition, w.loc);
    for (const ir::Equation &eq : w.equations)
      check(eq.residual, eq.loc);
    for (const ir::Reinit &r : w.reinits)
      check(r.value, r.loc);
    for (const ir::Assert &a : w.asserts) {
      check(a.condition, a.loc);
      for (ir::ExprRef v : a.messageValues)
        check(v, a.loc);
    }
  }
  for (const ir::Assert &a : model.asserts) {
    check(a.condition, a.loc);
    for (ir::ExprRef v : a.messageValues)
      check(v, a.loc);
  }
  return ok;
}

} // namespace ldae::frontend
