// Strongly connected components (Tarjan, iterative) and the block lower
// triangular (BLT) order of a matched square system built on them.
#pragma once

#include "graph/BipartiteGraph.h"

#include <vector>

namespace ldae::graph {

/// SCCs of the directed graph `succ` (node -> successors). Components come
/// out in reverse topological order: a component appears after every
/// component it reaches, i.e. dependencies first.
std::vector<std::vector<int>>
stronglyConnectedComponents(const std::vector<std::vector<int>> &succ);

/// BLT order of the rows of `g` under `m`: row r depends on row s when r
/// contains the column matched to s. Blocks (lists of rows) come in solve
/// order, each block's rows sorted. Unmatched rows and columns are ignored.
std::vector<std::vector<int>> bltBlocks(const BipartiteGraph &g,
                                        const Matching &m);

} // namespace ldae::graph
