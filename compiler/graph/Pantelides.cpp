// Pantelides' algorithm with an iterative augmenting-path search that
// remembers what it coloured, so each search costs what it visits and a
// 10^5-equation index-1 model is handled in linear time.
#include "graph/Pantelides.h"

#include "graph/Matching.h"

#include <algorithm>
#include <cassert>

namespace ldae::graph {

Pantelides::Pantelides(BipartiteGraph g, std::vector<int> varDiff)
    : g_(std::move(g)), varDiff_(std::move(varDiff)) {
  assert(static_cast<int>(varDiff_.size()) == g_.numCols);
  varPrev_.assign(g_.numCols, -1);
  for (int c = 0; c < g_.numCols; ++c)
    if (varDiff_[c] >= 0)
      varPrev_[varDiff_[c]] = c;
  eqDiff_.assign(g_.numRows(), -1);
  eqPrev_.assign(g_.numRows(), -1);
}

int Pantelides::derivativeColumn(int col) {
  if (varDiff_[col] >= 0)
    return varDiff_[col];
  int d = g_.addCol();
  varDiff_.push_back(-1);
  varPrev_.push_back(col);
  varDiff_[col] = d;
  m_.colMate.push_back(-1);
  colColor_.push_back(0);
  return d;
}

int Pantelides::addRow(std::vector<int> cols, int base) {
  int r = g_.addRow(std::move(cols));
  eqDiff_.push_back(-1);
  eqPrev_.push_back(base);
  eqDiff_[base] = r;
  m_.rowMate.push_back(-1);
  rowColor_.push_back(0);
  return r;
}

int Pantelides::timesDifferentiated(int row) const {
  int n = 0;
  for (int r = eqDiff_[row]; r >= 0; r = eqDiff_[r])
    ++n;
  return n;
}

int Pantelides::baseColumn(int col) const {
  while (varPrev_[col] >= 0)
    col = varPrev_[col];
  return col;
}

// Searches an augmenting path from `root` over active columns (those with no
// derivative), colouring what it visits. On success the matching is flipped
// along the path.
bool Pantelides::augment(int root) {
  struct Frame {
    int row;
    int next; // next edge to try
    int via;  // the column through which the row was reached (-1 at root)
  };
  std::vector<Frame> stack{{root, 0, -1}};
  rowColor_[root] = 1;
  coloredRows_.push_back(root);
  auto active = [&](int c) { return varDiff_[c] < 0; };
  // Cheap assignment first: a free active column in the newly reached row.
  auto freeColumn = [&](int r) {
    for (int c : g_.rows[r])
      if (active(c) && m_.colMate[c] < 0)
        return c;
    return -1;
  };
  int free = freeColumn(root);
  while (free < 0) {
    Frame &f = stack.back();
    const std::vector<int> &adj = g_.rows[f.row];
    if (f.next == static_cast<int>(adj.size())) {
      stack.pop_back();
      if (stack.empty())
        return false;
      continue;
    }
    int c = adj[f.next++];
    if (!active(c) || colColor_[c])
      continue;
    colColor_[c] = 1;
    coloredCols_.push_back(c);
    int w = m_.colMate[c];
    if (w < 0 || rowColor_[w])
      continue;
    rowColor_[w] = 1;
    coloredRows_.push_back(w);
    stack.push_back({w, 0, c});
    free = freeColumn(w);
  }
  // Flip: the last row takes the free column, each row takes the column
  // its successor was reached through.
  int take = free;
  for (int i = static_cast<int>(stack.size()) - 1; i >= 0; --i) {
    int r = stack[i].row;
    if (m_.rowMate[r] < 0)
      ++m_.size;
    m_.rowMate[r] = take;
    m_.colMate[take] = r;
    take = stack[i].via;
  }
  return true;
}

Pantelides::Result Pantelides::run(const DifferentiateRow &differentiate) {
  Result result;
  const int n = g_.numRows();

  // Termination check: match rows to variables with orders merged.
  BipartiteGraph merged(n, g_.numCols);
  for (int r = 0; r < n; ++r) {
    std::vector<int> &row = merged.rows[r];
    for (int c : g_.rows[r])
      row.push_back(baseColumn(c));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  std::vector<char> isBase(g_.numCols);
  for (int c = 0; c < g_.numCols; ++c)
    isBase[c] = varPrev_[c] < 0;
  Matching mm = maximumMatching(merged, isBase);
  if (mm.size < n) {
    result.status = Status::StructurallySingular;
    result.merged = std::move(mm);
    result.mergedGraph = std::move(merged);
    result.mergedCols = std::move(isBase);
    return result;
  }

  // A maximum matching on the active columns is a valid start: Pantelides
  // only needs every matched row to stay matched.
  std::vector<char> activeMask(g_.numCols);
  for (int c = 0; c < g_.numCols; ++c)
    activeMask[c] = varDiff_[c] < 0;
  m_ = maximumMatching(g_, activeMask);
  rowColor_.assign(g_.numRows(), 0);
  colColor_.assign(g_.numCols, 0);

  // With the merged check passed no equation is differentiated more than
  // there are equations; exceeding that means the hook's incidence
  // contradicts the structure, reported instead of looping.
  const int limit = n + 1;
  for (int k = 0; k < n; ++k) {
    // An equation differentiated while matching an earlier one is
    // represented by its highest derivative.
    int row = k;
    while (eqDiff_[row] >= 0)
      row = eqDiff_[row];
    for (int times = 0; m_.rowMate[row] < 0; ++times) {
      if (times > limit) {
        result.status = Status::NoProgress;
        return result;
      }
      coloredRows_.clear();
      coloredCols_.clear();
      bool found = augment(row);
      std::vector<int> rows = coloredRows_, cols = coloredCols_;
      for (int r : rows)
        rowColor_[r] = 0;
      for (int c : cols)
        colColor_[c] = 0;
      if (found)
        break;
      // Differentiate every coloured variable and equation; the matching
      // moves up to the derivatives.
      for (int c : cols)
        derivativeColumn(c);
      for (int r : rows) {
        std::vector<int> inc = differentiate(r);
        addRow(std::move(inc), r);
      }
      for (int c : cols) {
        int r = m_.colMate[c];
        if (r < 0)
          continue;
        int dr = eqDiff_[r], dc = varDiff_[c];
        m_.rowMate[r] = -1;
        m_.colMate[c] = -1;
        m_.rowMate[dr] = dc;
        m_.colMate[dc] = dr;
      }
      row = eqDiff_[row];
    }
  }
  return result;
}

} // namespace ldae::graph
