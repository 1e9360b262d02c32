// The coarse Dulmage–Mendelsohn decomposition of a bipartite graph under a
// maximum matching: the over-determined part (rows reachable by alternating
// paths from unmatched rows), the under-determined part (columns reachable
// from unmatched columns) and the well-determined rest. It names exactly the
// equations and unknowns a structurally singular system gets wrong.
#pragma once

#include "graph/BipartiteGraph.h"

#include <vector>

namespace ldae::graph {

struct DmPart {
  std::vector<int> rows; // sorted
  std::vector<int> cols; // sorted
};

struct DmDecomposition {
  /// More equations than unknowns: every row reachable from an unmatched
  /// row, and the columns they contain.
  DmPart over;
  /// More unknowns than equations: every column reachable from an
  /// unmatched column, and the rows containing them.
  DmPart under;
  /// The square, structurally nonsingular rest.
  DmPart well;
  bool singular() const {
    return !over.rows.empty() || !under.cols.empty();
  }
};

/// Decomposes `g` under the maximum matching `m`. When `colAllowed` is
/// non-empty, columns without `colAllowed[c]` are left out entirely.
DmDecomposition dulmageMendelsohn(const BipartiteGraph &g, const Matching &m,
                                  const std::vector<char> &colAllowed = {});

/// Splits the rows and columns of `part` into connected pieces (rows joined
/// through shared columns), each sorted, pieces ordered by first row.
std::vector<DmPart> connectedPieces(const BipartiteGraph &g,
                                    const DmPart &part);

} // namespace ldae::graph
