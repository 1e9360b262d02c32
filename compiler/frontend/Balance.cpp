// The count check of a flat model: as many equations as unknowns. When the
// counts differ, a maximum matching of equations to the variables they
// contain names the unknowns no equation determines (too few equations)
// or the equations left over (too many), with their components.
#include "frontend/Frontend.h"

#include "ir/Query.h"

#include <algorithm>

namespace ldae::frontend {
namespace {

constexpr size_t kMaxNotes = 8;

/// Maximum bipartite matching by augmenting paths (iterative DFS, so
/// long chains do not overflow the stack). Returns eq -> unknown or -1.
std::vector<int> maximumMatching(const std::vector<std::vector<int>> &adj,
                                 size_t numUnknowns, std::vector<int> &matchU) {
  std::vector<int> matchE(adj.size(), -1);
  matchU.assign(numUnknowns, -1);
  // Cheap greedy start.
  for (size_t e = 0; e < adj.size(); ++e)
    for (int u : adj[e])
      if (matchU[u] < 0) {
        matchU[u] = static_cast<int>(e);
        matchE[e] = u;
        break;
      }
  std::vector<unsigned> visited(numUnknowns, 0);
  unsigned stamp = 0;
  for (size_t root = 0; root < adj.size(); ++root) {
    if (matchE[root] >= 0)
      continue;
    ++stamp;
    // Stack of (equation, next edge index); parent unknown per level.
    std::vector<std::pair<int, size_t>> stack{{static_cast<int>(root), 0}};
    std::vector<int> via; // unknown used to reach stack[i + 1]
    bool found = false;
    while (!stack.empty() && !found) {
      auto &[e, next] = stack.back();
      if (next == adj[e].size()) {
        stack.pop_back();
        if (!via.empty())
          via.pop_back();
        continue;
      }
      int u = adj[e][next++];
      if (visited[u] == stamp)
        continue;
      visited[u] = stamp;
      if (matchU[u] < 0) {
        // Augment along the stack.
        via.push_back(u);
        for (size_t i = 0; i < stack.size(); ++i) {
          int eq = stack[i].first, un = via[i];
          matchE[eq] = un;
          matchU[un] = eq;
        }
        found = true;
      } else {
        via.push_back(u);
        stack.push_back({matchU[u], 0});
      }
    }
  }
  return matchE;
}

std::string inComponent(const std::string &component) {
  return component.empty() ? "" : " in component '" + component + "'";
}

} // namespace

bool checkBalance(const ir::Model &model, DiagnosticEngine &diags,
                  bool asError) {
  // Discrete variables assigned in when-clauses are not unknowns of the
  // continuous system.
  std::vector<bool> whenAssigned(model.variables.size(), false);
  for (const ir::WhenClause &w : model.whenClauses) {
    for (const ir::Equation &eq : w.equations)
      for (ir::VarKey k : ir::freeVariables(eq.residual))
        if (model.variables[k.var].isDiscrete)
          whenAssigned[k.var] = true;
  }
  std::vector<int> unknownOf(model.variables.size(), -1);
  std::vector<ir::VarId> unknowns;
  for (ir::VarId v = 0; v < model.variables.size(); ++v)
    if (!whenAssigned[v]) {
      unknownOf[v] = static_cast<int>(unknowns.size());
      unknowns.push_back(v);
    }
  size_t numEq = model.equations.size(), numUnknowns = unknowns.size();
  if (numEq == numUnknowns)
    return true;

  std::vector<std::vector<int>> adj(numEq);
  for (size_t e = 0; e < numEq; ++e) {
    for (ir::VarKey k : ir::freeVariables(model.equations[e].residual))
      if (unknownOf[k.var] >= 0)
        adj[e].push_back(unknownOf[k.var]);
    std::sort(adj[e].begin(), adj[e].end());
    adj[e].erase(std::unique(adj[e].begin(), adj[e].end()), adj[e].end());
  }
  std::vector<int> matchU;
  std::vector<int> matchE = maximumMatching(adj, numUnknowns, matchU);

  Diagnostic &d = diags.report(asError ? DiagId::ErrUnbalanced
                                       : DiagId::WarnUnbalanced,
                               model.loc,
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
        const ir::Equation &eq = model.equations[e];
        DiagnosticEngine::addNote(d, eq.loc, DiagId::NoteSurplusEquation,
                                  {eq.text, inComponent(eq.component)});
        ++notes;
      }
  }
  return false;
}

} // namespace ldae::frontend
