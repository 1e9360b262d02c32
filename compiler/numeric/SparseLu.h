// A square sparse matrix in compressed sparse columns (the layout of the
// ABI's jac_colptr/jac_rowind) and its LU factorization by KLU, with a
// 1-norm condition estimate. The runtime's large-model paths (index-1
// test, index-1 Newton, failure reports) use it instead of dense n x n
// matrices: factoring a circuit-like Jacobian costs about O(nnz), a dense
// LU O(n^3).
#pragma once

#include <memory>
#include <vector>

namespace ldae::numeric {

/// n x n, CSC; rows within a column need not be sorted (no duplicates).
struct CscMatrix {
  int n = 0;
  std::vector<int> colptr; ///< n + 1
  std::vector<int> rowind; ///< nnz
  std::vector<double> values;

  int nnz() const { return colptr.empty() ? 0 : colptr[n]; }
  /// Largest |value| (0 for an empty matrix).
  double maxAbs() const;
  /// y = A x.
  void multiply(const double *x, double *y) const;
  /// A^T, O(nnz).
  CscMatrix transposed() const;
};

class SparseLu {
public:
  SparseLu();
  ~SparseLu();
  SparseLu(const SparseLu &) = delete;
  SparseLu &operator=(const SparseLu &) = delete;

  /// Factors `a` (kept by reference until the next factor call: the
  /// condition estimate reads it). False when KLU meets a zero pivot or
  /// fails; then singularColumn() may name the column.
  bool factor(const CscMatrix &a);
  /// Reciprocal of KLU's 1-norm condition estimate (Hager/Higham); 0 when
  /// not factored or the estimate fails.
  double rcondEstimate();
  /// Solves A x = b (transposed: A^T x = b) in place; false on failure.
  bool solve(double *b, bool transposed = false);
  /// The column of the zero pivot after a failed factor(), or -1.
  int singularColumn() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace ldae::numeric
