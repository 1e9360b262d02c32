// Pass "blt": matches each residual of the index-1 system to what it
// solves for (an algebraic unknown or a state's derivative) and orders the
// residuals in block lower triangular form (Tarjan). A failed matching
// means index reduction left a singular system: reported, never ignored.
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/Matching.h"
#include "graph/Scc.h"
#include "ir/Print.h"

namespace ldae::passes {

bool bltOrder(PassContext &ctx, const ir::DaeSystem &sys, bool allowSingular,
              BltResult &out) {
  out = BltResult{};
  for (size_t set = 0; set < sys.stateSets.size(); ++set) {
    out.reads.push_back(systemReads(sys, set));
    graph::BipartiteGraph g = systemGraph(sys, set, out.reads.back(), true);
    graph::Matching m = graph::maximumMatching(g);
    if (m.size < g.numRows() && !allowSingular) {
      // Name what is wrong, as for the model.
      SingularityNames names;
      names.rowLoc = [&](int r) {
        return r < static_cast<int>(sys.residualLocs.size())
                   ? sys.residualLocs[r]
                   : SourceLoc{};
      };
      names.rowText = [&](int r) {
        return ir::printLsd(sys.stateSets[set].residuals[r], &ctx.model) +
               " = 0";
      };
      names.colName = [&](int c) { return sys.unknowns[c].name; };
      names.colLoc = [&](int c) { return sys.unknowns[c].loc; };
      diagnoseSingular(ctx, "index-reduced system", g, m, names, {}, false);
      return false;
    }
    if (set == 0) {
      ctx.report.bltBlocks.clear();
      for (const std::vector<int> &b : graph::bltBlocks(g, m))
        ctx.report.bltBlocks.push_back(static_cast<int>(b.size()));
    }
    out.graphs.push_back(std::move(g));
    out.matchings.push_back(std::move(m));
  }
  return true;
}

namespace {

class BltPass : public TypedPass<BltPass, Reads<ir::DaeSystem>, Updates<>,
                                 Produces<BltResult>> {
public:
  explicit BltPass(const BltOptions &opts)
      : TypedPass(PassId::Blt), opts_(opts) {}

  bool runOn(PassContext &ctx, const ir::DaeSystem &sys, BltResult &out) {
    return bltOrder(ctx, sys, opts_.allowSingular, out);
  }

private:
  BltOptions opts_;
};

} // namespace

std::unique_ptr<Pass> createBltPass(const BltOptions &opts) {
  return std::make_unique<BltPass>(opts);
}

} // namespace ldae::passes
