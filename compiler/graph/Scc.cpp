// Tarjan's algorithm with an explicit stack so chains of 10^5 equations do
// not overflow the call stack.
#include "graph/Scc.h"

#include <algorithm>

namespace ldae::graph {

std::vector<std::vector<int>>
stronglyConnectedComponents(const std::vector<std::vector<int>> &succ) {
  const int n = static_cast<int>(succ.size());
  std::vector<int> index(n, -1), low(n, 0), edge(n, 0);
  std::vector<char> onStack(n, 0);
  std::vector<int> stack, work;
  std::vector<std::vector<int>> comps;
  int counter = 0;
  for (int root = 0; root < n; ++root) {
    if (index[root] >= 0)
      continue;
    work.push_back(root);
    while (!work.empty()) {
      int v = work.back();
      if (index[v] < 0) {
        index[v] = low[v] = counter++;
        stack.push_back(v);
        onStack[v] = 1;
      }
      if (edge[v] < static_cast<int>(succ[v].size())) {
        int w = succ[v][edge[v]++];
        if (index[w] < 0)
          work.push_back(w);
        else if (onStack[w])
          low[v] = std::min(low[v], index[w]);
        continue;
      }
      work.pop_back();
      if (!work.empty())
        low[work.back()] = std::min(low[work.back()], low[v]);
      if (low[v] == index[v]) {
        std::vector<int> comp;
        int w;
        do {
          w = stack.back();
          stack.pop_back();
          onStack[w] = 0;
          comp.push_back(w);
        } while (w != v);
        std::sort(comp.begin(), comp.end());
        comps.push_back(std::move(comp));
      }
    }
  }
  return comps;
}

std::vector<std::vector<int>> bltBlocks(const BipartiteGraph &g,
                                        const Matching &m) {
  std::vector<std::vector<int>> succ(g.numRows());
  for (int r = 0; r < g.numRows(); ++r) {
    if (m.rowMate[r] < 0)
      continue;
    for (int c : g.rows[r]) {
      int s = m.colMate[c];
      if (s >= 0 && s != r)
        succ[r].push_back(s);
    }
  }
  std::vector<std::vector<int>> blocks;
  for (std::vector<int> &comp : stronglyConnectedComponents(succ))
    if (m.rowMate[comp.front()] >= 0)
      blocks.push_back(std::move(comp));
  return blocks;
}

} // namespace ldae::graph
