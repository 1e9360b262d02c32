// The count check of a flat model: as many equations as unknowns. When the
// counts differ, a maximum matching of equations to the variables they
// contain names the unknowns no equation determines (too few equations)
// or the equations left over (too many), with their components.
#include "frontend/Frontend.h"

#include "graph/Matching.h"
#include "ir/Discrete.h"
#include "ir/Query.h"

#include <algorithm>

namespace ldae::frontend {
namespace {

constexpr size_t kMaxNotes = 8;

std::string inComponent(const std::string &component) {
  return component.empty() ? "" : " in component '" + component + "'";
}

} // namespace

bool checkBalance(const ir::Model &model, DiagnosticEngine &diags) {
  // Discrete variables (Boolean, Integer, discrete Real, assigned in a
  // when-clause) are not unknowns of the continuous system, and the
  // equations of discrete values that define them are not its equations.
  const std::vector<bool> discrete = ir::discreteVariables(model);
  std::vector<int> unknownOf(model.variables.size(), -1);
  std::vector<ir::VarId> unknowns;
  for (ir::VarId v = 0; v < model.variables.size(); ++v)
    if (!discrete[v]) {
      unknownOf[v] = static_cast<int>(unknowns.size());
      unknowns.push_back(v);
    }
  std::vector<size_t> continuous;
  for (size_t e = 0; e < model.equations.size(); ++e)
    if (!ir::isDiscreteEquation(model.equations[e].residual, discrete))
      continuous.push_back(e);
  size_t numEq = continuous.size(), numUnknowns = unknowns.size();
  if (numEq == numUnknowns)
    return true;

  graph::BipartiteGraph g(static_cast<int>(numEq),
                          static_cast<int>(numUnknowns));
  for (size_t e = 0; e < numEq; ++e) {
    std::vector<int> &row = g.rows[e];
    for (ir::VarKey k :
         ir::freeVariables(model.equations[continuous[e]].residual))
      if (unknownOf[k.var] >= 0)
        row.push_back(unknownOf[k.var]);
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  graph::Matching matching = graph::maximumMatching(g);
  const std::vector<int> &matchU = matching.colMate;
  const std::vector<int> &matchE = matching.rowMate;

  Diagnostic &d = diags.report(DiagId::WarnUnbalanced, model.loc,
                               {model.name, std::to_string(numEq),
                                std::to_string(numUnknowns)});
  size_t notes = 0;
  if (numUnknowns > numEq) {
    for (size_t u = 0; u < numUnknowns && notes < kMaxNotes; ++u)
      if (matchU[u] < 0) {
        const ir::Variable &var = model.variables[unknowns[u]];
        DiagnosticEngine::addNote(d, var.loc, DiagId::NoteUndeterminedVariable,
                                  {var.name, inComponent(var.component)});
        ++notes;
      }
  } else {
    for (size_t e = 0; e < numEq && notes < kMaxNotes; ++e)
      if (matchE[e] < 0) {
        const ir::Equation &eq = model.equations[continuous[e]];
        DiagnosticEngine::addNote(d, eq.loc, DiagId::NoteSurplusEquation,
                                  {eq.text, inComponent(eq.component)});
        ++notes;
      }
  }
  return false;
}

} // namespace ldae::frontend
