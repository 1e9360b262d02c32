// Alternating-path searches from the unmatched vertices; linear time.
#include "graph/DulmageMendelsohn.h"

#include <algorithm>
#include <numeric>

namespace ldae::graph {

namespace {
std::vector<int> marked(const std::vector<char> &mark) {
  std::vector<int> out;
  for (int i = 0; i < static_cast<int>(mark.size()); ++i)
    if (mark[i])
      out.push_back(i);
  return out;
}
} // namespace

DmDecomposition dulmageMendelsohn(const BipartiteGraph &g, const Matching &m,
                                  const std::vector<char> &colAllowed) {
  auto allowed = [&](int c) { return colAllowed.empty() || colAllowed[c]; };
  const int nr = g.numRows(), nc = g.numCols;
  std::vector<std::vector<int>> cols = g.columns();

  // Over-determined: unmatched row -> its columns -> their matched rows.
  std::vector<char> overRow(nr, 0), overCol(nc, 0);
  std::vector<int> queue;
  for (int r = 0; r < nr; ++r)
    if (m.rowMate[r] < 0) {
      overRow[r] = 1;
      queue.push_back(r);
    }
  for (size_t q = 0; q < queue.size(); ++q)
    for (int c : g.rows[queue[q]]) {
      if (overCol[c] || !allowed(c))
        continue;
      overCol[c] = 1;
      int s = m.colMate[c];
      if (s >= 0 && !overRow[s]) {
        overRow[s] = 1;
        queue.push_back(s);
      }
    }

  // Under-determined: unmatched column -> its rows -> their matched columns.
  std::vector<char> underRow(nr, 0), underCol(nc, 0);
  queue.clear();
  for (int c = 0; c < nc; ++c)
    if (m.colMate[c] < 0 && allowed(c)) {
      underCol[c] = 1;
      queue.push_back(c);
    }
  for (size_t q = 0; q < queue.size(); ++q)
    for (int r : cols[queue[q]]) {
      if (underRow[r])
        continue;
      underRow[r] = 1;
      int c = m.rowMate[r];
      if (c >= 0 && !underCol[c]) {
        underCol[c] = 1;
        queue.push_back(c);
      }
    }

  DmDecomposition dm;
  dm.over = {marked(overRow), marked(overCol)};
  dm.under = {marked(underRow), marked(underCol)};
  std::vector<char> wellRow(nr), wellCol(nc);
  for (int r = 0; r < nr; ++r)
    wellRow[r] = !overRow[r] && !underRow[r];
  for (int c = 0; c < nc; ++c)
    wellCol[c] = allowed(c) && !overCol[c] && !underCol[c];
  dm.well = {marked(wellRow), marked(wellCol)};
  return dm;
}

std::vector<DmPart> connectedPieces(const BipartiteGraph &g,
                                    const DmPart &part) {
  // Union-find over the part's rows, joined by shared columns.
  std::vector<int> parent(g.numRows());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> inCols(g.numCols, 0);
  for (int c : part.cols)
    inCols[c] = 1;
  std::vector<int> firstRowOfCol(g.numCols, -1);
  for (int r : part.rows)
    for (int c : g.rows[r]) {
      if (!inCols[c])
        continue;
      if (firstRowOfCol[c] < 0)
        firstRowOfCol[c] = r;
      else
        parent[find(r)] = find(firstRowOfCol[c]);
    }
  std::vector<DmPart> pieces;
  std::vector<int> pieceOf(g.numRows(), -1);
  for (int r : part.rows) {
    int root = find(r);
    if (pieceOf[root] < 0) {
      pieceOf[root] = static_cast<int>(pieces.size());
      pieces.emplace_back();
    }
    pieces[pieceOf[root]].rows.push_back(r);
  }
  for (int c : part.cols) {
    if (firstRowOfCol[c] < 0) {
      // A column no row of the part contains (an unknown nothing mentions).
      pieces.push_back({{}, {c}});
      continue;
    }
    pieces[pieceOf[find(firstRowOfCol[c])]].cols.push_back(c);
  }
  return pieces;
}

} // namespace ldae::graph
