// Maximum bipartite matching (Hopcroft–Karp, O(E sqrt(V))), with an
// optional mask of the columns that may be used. Deterministic: rows and
// columns are visited in index order, so equal inputs give equal matchings.
#pragma once

#include "graph/BipartiteGraph.h"

#include <vector>

namespace ldae::graph {

/// A maximum matching of `g`. When `colAllowed` is non-empty only columns
/// with `colAllowed[c]` take part. Starts from `initial` when given (it must
/// be a valid matching of `g` over allowed columns).
Matching maximumMatching(const BipartiteGraph &g,
                         const std::vector<char> &colAllowed = {},
                         const Matching *initial = nullptr);

} // namespace ldae::graph
