// Pass "blt": matches each residual of the index-1 system to what it
// solves for (an algebraic unknown or a state's derivative) and orders the
// residuals in block lower triangular form (Tarjan). A failed matching
// means index reduction left a singular system: reported, never ignored.
#include "passes/AnalysisState.h"
#include "passes/SystemStructure.h"

#include "graph/Matching.h"
#include "graph/Scc.h"

namespace ldae::passes {

bool runBlt(AnalysisState &s) {
  if (!s.haveSystem)
    return true;
  const ir::DaeSystem &sys = s.system;
  s.systemGraphs.clear();
  s.systemMatchings.clear();
  s.systemReads.clear();
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    s.systemReads.push_back(systemReads(sys, set));
    graph::BipartiteGraph g = systemGraph(sys, set, s.systemReads.back(), true);
    graph::Matching m = graph::maximumMatching(g);
    // The unreduced system of `--method raw` is singular whenever the
    // model's index exceeds one: that is what raw is for.
    if (m.size < g.numRows() && s.opts.method != "raw") {
      // Name what is wrong, as for the model.
      SingularityNames names;
      names.rowLoc = [&](int r) {
        return r < static_cast<int>(sys.residualLocs.size())
                   ? sys.residualLocs[r]
                   : SourceLoc{};
      };
      names.rowText = [&](int r) {
        return ir::printLsd(sys.stateSets[set].residuals[r], &s.model) +
               " = 0";
      };
      names.colName = [&](int c) { return sys.unknowns[c].name; };
      names.colLoc = [&](int c) { return sys.unknowns[c].loc; };
      diagnoseSingular(s, "index-reduced system", g, m, names, {}, false);
      return false;
    }
    if (set == 0) {
      s.result.bltBlocks.clear();
      for (const std::vector<int> &b : graph::bltBlocks(g, m))
        s.result.bltBlocks.push_back(static_cast<int>(b.size()));
    }
    s.systemGraphs.push_back(std::move(g));
    s.systemMatchings.push_back(std::move(m));
  }
  return true;
}

} // namespace ldae::passes
