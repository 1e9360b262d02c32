// Pantelides' algorithm (1988) on an integer structure, in the style of
// StateSelection.jl: the structure is an incidence graph whose columns are
// variables at one derivative order (`varDiff[c]` is the column of the
// derivative of c, or -1) and whose rows are equations (`eqDiff[r]` the row
// of the derivative of r, or -1). Differentiating an equation is a hook the
// symbolic layer supplies, so cancellations it finds are respected.
//
// Termination: Pantelides ends exactly when every equation can be matched
// to a distinct variable with derivative orders merged. `run` checks that
// first (and fails with the rows it could not match) instead of looping.
#pragma once

#include "graph/BipartiteGraph.h"

#include <functional>
#include <vector>

namespace ldae::graph {

class Pantelides {
public:
  /// `g` has every variable at every order it occurs as a column, chained
  /// by `varDiff` (col -> col of its derivative, or -1).
  Pantelides(BipartiteGraph g, std::vector<int> varDiff);

  /// Makes (or returns) the column of the derivative of `col`.
  int derivativeColumn(int col);

  /// Returns the incidence (columns) of the time derivative of row `row`;
  /// it may call derivativeColumn for the new columns it needs.
  using DifferentiateRow = std::function<std::vector<int>(int row)>;

  enum class Status {
    Ok,
    StructurallySingular, // the merged graph has no complete matching
    NoProgress // the hook's incidence broke the structure (a bug guard)
  };
  struct Result {
    Status status = Status::Ok;
    /// For StructurallySingular: a maximum matching of the merged graph
    /// (rows = original rows, cols = base variables), for diagnosis.
    Matching merged;
    BipartiteGraph mergedGraph;
    std::vector<char> mergedCols; // the base columns taking part
  };

  /// Runs the algorithm over rows 0..numRows-1 present at construction.
  Result run(const DifferentiateRow &differentiate);

  const BipartiteGraph &graph() const { return g_; }
  const std::vector<int> &varDiff() const { return varDiff_; }
  const std::vector<int> &eqDiff() const { return eqDiff_; }
  /// The column a column differentiates (inverse of varDiff), or -1.
  const std::vector<int> &varBase() const { return varPrev_; }
  /// The row a row was differentiated from, or -1.
  const std::vector<int> &eqBase() const { return eqPrev_; }
  /// The final matching of the highest-order rows to highest-order columns.
  const Matching &matching() const { return m_; }
  /// Number of differentiations of row r (length of its eqDiff chain).
  int timesDifferentiated(int row) const;
  /// The original column of a variable (first of its derivative chain).
  int baseColumn(int col) const;

private:
  bool augment(int root);
  int addRow(std::vector<int> cols, int base);

  BipartiteGraph g_;
  std::vector<int> varDiff_, varPrev_, eqDiff_, eqPrev_;
  Matching m_;
  std::vector<char> rowColor_, colColor_;
  std::vector<int> coloredRows_, coloredCols_;
};

} // namespace ldae::graph
