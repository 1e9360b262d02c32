// Pass "matching": puts unknowns and equations in a canonical order (by
// name and by equation content, never by source position) and matches
// equations to unknowns with derivative orders merged. A complete matching
// is exactly the condition under which Pantelides' algorithm ends; the
// "dm" pass explains a failure.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/Matching.h"
#include "ir/Query.h"

#include <algorithm>
#include <numeric>

namespace ldae::passes {

namespace {

class MatchingPass
    : public TypedPass<MatchingPass, Reads<AliasResult>, Updates<>,
                       Produces<MatchingResult>> {
public:
  MatchingPass() : TypedPass(PassId::Matching) {}
  bool runOn(PassContext &ctx, const AliasResult &alias, MatchingResult &s);
};

bool MatchingPass::runOn(PassContext &ctx, const AliasResult &alias,
                         MatchingResult &s) {
  ir::Model &m = ctx.model;
  const size_t nv = m.variables.size();
  auto eliminated = [&](ir::VarId v) {
    return v < alias.eliminated.size() && alias.eliminated[v];
  };

  for (ir::VarId v = 0; v < nv; ++v)
    if (!eliminated(v) && !m.variables[v].isDiscrete)
      s.unknowns.push_back(v);
  const std::vector<int> &rank = ctx.nameRanks();
  std::sort(s.unknowns.begin(), s.unknowns.end(),
            [&](ir::VarId a, ir::VarId b) { return rank[a] < rank[b]; });
  s.unknownIndex.assign(nv, -1);
  for (size_t j = 0; j < s.unknowns.size(); ++j)
    s.unknownIndex[s.unknowns[j]] = static_cast<int>(j);

  // Equation keys: the unknowns they contain (canonical rank and order),
  // then the user's text, then the printed residual.
  struct Key {
    std::vector<std::pair<int, unsigned>> vars;
    std::string text;
    std::string printed;
    auto operator<=>(const Key &) const = default;
  };
  const size_t ne = m.equations.size();
  std::vector<Key> keys(ne);
  std::vector<std::vector<ir::VarKey>> inc(ne);
  for (size_t i = 0; i < ne; ++i) {
    for (ir::VarKey k : variablesOf(m.equations[i].residual))
      if (k.var < nv && s.unknownIndex[k.var] >= 0) {
        inc[i].push_back(k);
        keys[i].vars.emplace_back(s.unknownIndex[k.var], k.order);
      }
    std::sort(keys[i].vars.begin(), keys[i].vars.end());
  }
  s.equations.resize(ne);
  std::iota(s.equations.begin(), s.equations.end(), 0);
  std::sort(s.equations.begin(), s.equations.end(),
            [&](int a, int b) { return keys[a].vars < keys[b].vars; });
  // Texts and printed residuals only where the cheaper key ties.
  for (size_t i = 0; i + 1 < ne; ++i) {
    int a = s.equations[i], b = s.equations[i + 1];
    if (keys[a].vars == keys[b].vars) {
      for (int e : {a, b}) {
        keys[e].text = m.equations[e].text;
        if (keys[e].printed.empty())
          keys[e].printed = ir::printLsd(m.equations[e].residual, &m);
      }
    }
  }
  std::stable_sort(s.equations.begin(), s.equations.end(),
                   [&](int a, int b) { return keys[a] < keys[b]; });

  s.originalOrder.assign(s.unknowns.size(), 0);
  s.merged = graph::BipartiteGraph(static_cast<int>(ne),
                                   static_cast<int>(s.unknowns.size()));
  for (size_t r = 0; r < ne; ++r) {
    std::vector<int> &row = s.merged.rows[r];
    for (ir::VarKey k : inc[s.equations[r]]) {
      int j = s.unknownIndex[k.var];
      s.originalOrder[j] = std::max<int>(s.originalOrder[j], k.order);
      row.push_back(j);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  s.matching = graph::maximumMatching(s.merged);
  return true;
}

} // namespace

std::unique_ptr<Pass> createMatchingPass() {
  return std::make_unique<MatchingPass>();
}

} // namespace ldae::passes
