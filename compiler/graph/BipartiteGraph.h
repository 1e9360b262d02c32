// The bipartite incidence graph every structural algorithm works on: rows
// are equations, columns are unknowns, both plain integers. Knows nothing of
// the IR; the passes translate equations and variables to indices and back.
#pragma once

#include <cassert>
#include <cstddef>
#include <vector>

namespace ldae::graph {

/// Rows (equations) with the columns (unknowns) each one contains.
struct BipartiteGraph {
  int numCols = 0;
  std::vector<std::vector<int>> rows;

  BipartiteGraph() = default;
  BipartiteGraph(int numRows, int numCols) : numCols(numCols), rows(numRows) {}

  int numRows() const { return static_cast<int>(rows.size()); }
  /// Adds an edge; callers add each (row, col) pair once.
  void addEdge(int row, int col) {
    assert(row >= 0 && row < numRows() && col >= 0 && col < numCols);
    rows[row].push_back(col);
  }
  /// Appends a row with the given columns; returns its index.
  int addRow(std::vector<int> cols) {
    rows.push_back(std::move(cols));
    return numRows() - 1;
  }
  /// Appends a column; returns its index.
  int addCol() { return numCols++; }
  /// The transposed adjacency: for each column, the rows containing it.
  std::vector<std::vector<int>> columns() const;
};

/// A matching: `rowMate[r]` is the column matched to row r or -1, and
/// `colMate[c]` the row matched to column c or -1.
struct Matching {
  std::vector<int> rowMate;
  std::vector<int> colMate;
  int size = 0;

  Matching() = default;
  Matching(int numRows, int numCols)
      : rowMate(numRows, -1), colMate(numCols, -1) {}
  void match(int row, int col) {
    if (rowMate[row] < 0)
      ++size;
    rowMate[row] = col;
    colMate[col] = row;
  }
};

} // namespace ldae::graph
