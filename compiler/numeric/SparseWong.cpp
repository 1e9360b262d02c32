// The Wong sequences of a sparse pencil by reduction (see SparseWong.h).
//
// Rank decisions are scale-free: an entry produced by a row operation is
// zero when it cancelled to below `tol` times its operands; a vector built
// as M v is zero when its norm is below `tol` times |||M| |v|||, the size
// it would have without cancellation; the remaining decisions are on
// orthonormal bases.
#include "numeric/SparseWong.h"

#include <optional>

#include "numeric/SparseLu.h"
#include "numeric/WongSequence.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace ldae::numeric {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void densePencil(const SparsePencil &p, MatrixXd &E, MatrixXd &F) {
  E = MatrixXd::Zero(p.rows, p.cols);
  F = MatrixXd::Zero(p.rows, p.cols);
  for (const SparsePencil::Entry &e : p.E)
    E(e.row, e.col) += e.value;
  for (const SparsePencil::Entry &e : p.F)
    F(e.row, e.col) += e.value;
}

namespace {

/// Rank-decision threshold on orthonormal or bound-normalized data.
constexpr double kBasisTol = 1e-9;

using SparseRow = std::unordered_map<int, double>;

/// Orthonormal basis of the columns of `m` whose columns are already
/// scaled so that cancellation shows as a small column.
MatrixXd orthColumns(const MatrixXd &m) {
  if (m.cols() == 0)
    return MatrixXd(m.rows(), 0);
  return rangeBasis(m, kBasisTol);
}

/// Orthonormal basis of the left null space of `m` (as rows), `m`'s
/// columns scaled as for orthColumns.
MatrixXd leftNullRows(const MatrixXd &m) {
  if (m.rows() == 0)
    return MatrixXd(0, 0);
  return nullBasis(m.transpose(), kBasisTol).transpose();
}

/// |M| |v| column by column for a sparse square M (the size of M v
/// without cancellation).
MatrixXd absProduct(const CscMatrix &m, const MatrixXd &v) {
  MatrixXd out = MatrixXd::Zero(m.n, v.cols());
  for (Index k = 0; k < v.cols(); ++k)
    for (int c = 0; c < m.n; ++c)
      for (int p = m.colptr[c]; p < m.colptr[c + 1]; ++p)
        out(m.rowind[p], k) += std::fabs(m.values[p] * v(c, k));
  return out;
}

MatrixXd sparseProduct(const CscMatrix &m, const MatrixXd &v) {
  MatrixXd out(m.n, v.cols());
  for (Index k = 0; k < v.cols(); ++k)
    m.multiply(v.col(k).data(), out.col(k).data());
  return out;
}

/// Scales each column of `prod` by the norm of the matching column of
/// `bound` (columns with a zero bound are zero).
MatrixXd scaledColumns(MatrixXd prod, const MatrixXd &bound) {
  for (Index k = 0; k < prod.cols(); ++k) {
    double b = bound.col(k).norm();
    prod.col(k) = b > 0 ? VectorXd(prod.col(k) / b)
                        : VectorXd::Zero(prod.rows());
  }
  return prod;
}

/// The pencil under reduction, row by row, with the column occupancy
/// needed to find pivots.
struct Reducer {
  int nr, nc;
  double tol;
  std::vector<SparseRow> E, F;
  std::vector<std::unordered_set<int>> eCol, fCol; // rows with an entry
  std::vector<char> rowAlive, colAlive;
  /// Index-1 pairs in elimination order, with the F row at that moment
  /// (its E part was zero): x_col = -(sum of the others) / pivot.
  struct Pair {
    int row, col;
    std::vector<std::pair<int, double>> f;
  };
  std::vector<Pair> pairs;
  std::vector<char> eRowPivot;
  std::vector<int> pivotColumn;  // by row: its E pivot's column
  std::vector<int> excess;       // differentiated columns without E pivot
  bool excessColumn = false;     // some could not be cleared
  /// Column operations x_p = x'_p - g_p x'_j clearing E's excess column
  /// j (E11 g = E12_j); made after the first `transformAt` pairs.
  struct Transform {
    int col;
    std::vector<std::pair<int, double>> g;
  };
  std::vector<Transform> transforms;
  size_t transformAt = 0;

  explicit Reducer(const SparsePencil &p, double tol)
      : nr(p.rows), nc(p.cols), tol(tol), E(nr), F(nr), eCol(nc), fCol(nc),
        rowAlive(nr, 1), colAlive(nc, 1), eRowPivot(nr, 0),
        pivotColumn(nr, -1) {
    for (const SparsePencil::Entry &e : p.E)
      E[e.row][e.col] += e.value;
    for (const SparsePencil::Entry &e : p.F)
      F[e.row][e.col] += e.value;
    for (int r = 0; r < nr; ++r) {
      prune(E[r], r, eCol);
      prune(F[r], r, fCol);
      equilibrate(r);
    }
  }

  /// Scales row r (E and F alike: a left multiplication, which the Wong
  /// sequences ignore) so that its E part, or its F part when E is zero,
  /// has largest entry 1: a capacitance of 1e-12 beside an inductance of
  /// 1 must not read as a rank drop of E11.
  void equilibrate(int r) {
    double s = 0;
    for (const auto &[c, v] : E[r].empty() ? F[r] : E[r])
      s = std::max(s, std::fabs(v));
    if (s == 0)
      return;
    for (auto &[c, v] : E[r])
      v /= s;
    for (auto &[c, v] : F[r])
      v /= s;
  }

  static void prune(SparseRow &row, int r,
                    std::vector<std::unordered_set<int>> &cols) {
    for (auto it = row.begin(); it != row.end();) {
      if (it->second == 0) {
        it = row.erase(it);
      } else {
        cols[it->first].insert(r);
        ++it;
      }
    }
  }

  /// row k += alpha * row i in one of the two matrices; an entry that
  /// cancels to below tol times its operands is dropped.
  void axpy(std::vector<SparseRow> &m, std::vector<std::unordered_set<int>> &cols,
            int k, int i, double alpha) {
    for (const auto &[c, v] : m[i]) {
      double add = alpha * v;
      auto it = m[k].find(c);
      double old = it == m[k].end() ? 0 : it->second;
      double sum = old + add;
      if (std::fabs(sum) <= tol * std::max(std::fabs(old), std::fabs(add))) {
        if (it != m[k].end()) {
          m[k].erase(it);
          cols[c].erase(k);
        }
      } else if (it != m[k].end()) {
        it->second = sum;
      } else {
        m[k].emplace(c, sum);
        cols[c].insert(k);
      }
    }
  }

  static std::vector<int> sorted(const std::unordered_set<int> &s) {
    std::vector<int> v(s.begin(), s.end());
    std::sort(v.begin(), v.end());
    return v;
  }

  /// Step 1: split off every 1 x 1 block (0, f) a row and a column both
  /// free of E allow. Returns whether it split any.
  bool splitIndexOnePairs() {
    bool any = false;
    for (bool changed = true; changed;) {
      changed = false;
      for (int i = 0; i < nr; ++i) {
        if (!rowAlive[i] || !E[i].empty())
          continue;
        double rowMax = 0;
        for (const auto &[c, v] : F[i])
          if (eCol[c].empty())
            rowMax = std::max(rowMax, std::fabs(v));
        if (rowMax == 0)
          continue;
        // Threshold pivoting, then the sparsest column (fewest updates),
        // then the lowest index (determinism).
        int best = -1;
        for (const auto &[c, v] : F[i]) {
          if (!eCol[c].empty() || std::fabs(v) < 0.1 * rowMax)
            continue;
          if (best < 0 || fCol[c].size() < fCol[best].size() ||
              (fCol[c].size() == fCol[best].size() && c < best))
            best = c;
        }
        eliminatePair(i, best);
        changed = any = true;
      }
    }
    return any;
  }

  void eliminatePair(int i, int j) {
    double pivot = F[i].at(j);
    for (int k : sorted(fCol[j])) {
      if (k == i)
        continue;
      axpy(F, fCol, k, i, -F[k].at(j) / pivot);
      F[k].erase(j);
      fCol[j].erase(k);
    }
    Pair pair{i, j, {}};
    for (const auto &[c, v] : F[i]) {
      pair.f.push_back({c, v});
      fCol[c].erase(i);
    }
    std::sort(pair.f.begin(), pair.f.end());
    pairs.push_back(std::move(pair));
    F[i].clear();
    rowAlive[i] = 0;
    colAlive[j] = 0;
  }

  /// Step 2: Gaussian elimination on E by rows (applied to F too), so that
  /// rows whose E part depends on others become E-free constraints.
  void compressE() {
    std::vector<int> cols;
    for (int c = 0; c < nc; ++c)
      if (colAlive[c] && !eCol[c].empty())
        cols.push_back(c);
    std::stable_sort(cols.begin(), cols.end(), [&](int a, int b) {
      return eCol[a].size() < eCol[b].size();
    });
    for (int j : cols) {
      int best = -1;
      for (int k : sorted(eCol[j]))
        if (!eRowPivot[k] &&
            (best < 0 || std::fabs(E[k].at(j)) > std::fabs(E[best].at(j))))
          best = k;
      if (best < 0) {
        excess.push_back(j); // only pivot rows read it
        continue;
      }
      eRowPivot[best] = 1;
      pivotColumn[best] = j;
      for (int k : sorted(eCol[j])) {
        if (eRowPivot[k])
          continue;
        double alpha = -E[k].at(j) / E[best].at(j);
        axpy(E, eCol, k, best, alpha);
        axpy(F, fCol, k, best, alpha);
        if (E[k].erase(j))
          eCol[j].erase(k);
      }
    }
  }

  /// Step 2b: a differentiated column that only pivot rows read (a
  /// capacitor between two nodes: C (e_a - e_b)' has one row, two
  /// columns) is cleared from E by a column operation with the pivot
  /// columns, x_p = x'_p - g_p x'_j with E11 g = E12_j; x'_j is then free of
  /// E (step 1 may pair it). False when E11 cannot be factored.
  bool clearExcessColumns() {
    transformAt = pairs.size();
    if (excess.empty())
      return true;
    std::vector<int> prow, pcolIndex(nc, -1), pcol;
    for (int r = 0; r < nr; ++r)
      if (rowAlive[r] && eRowPivot[r]) {
        pcolIndex[pivotColumn[r]] = int(prow.size());
        prow.push_back(r);
        pcol.push_back(pivotColumn[r]);
      }
    CscMatrix e11 = toCscRows(E, prow, pcolIndex, int(prow.size()));
    SparseLu lu;
    if (!prow.empty() && !lu.factor(e11))
      return false;
    for (int j : excess) {
      VectorXd g = VectorXd::Zero(prow.size());
      for (size_t k = 0; k < prow.size(); ++k) {
        auto it = E[prow[k]].find(j);
        if (it != E[prow[k]].end())
          g(k) = it->second;
      }
      lu.solve(g.data());
      Transform t{j, {}};
      std::unordered_map<int, std::pair<double, double>> delta; // sum, bound
      for (size_t k = 0; k < prow.size(); ++k) {
        if (g(k) == 0)
          continue;
        t.g.push_back({pcol[k], g(k)});
        for (int r : fCol[pcol[k]]) {
          double v = g(k) * F[r].at(pcol[k]);
          delta[r].first -= v;
          delta[r].second += std::fabs(v);
        }
      }
      for (const auto &[r, d] : delta) {
        auto it = F[r].find(j);
        double old = it == F[r].end() ? 0 : it->second;
        double sum = old + d.first;
        if (std::fabs(sum) <= tol * std::max(std::fabs(old), d.second)) {
          if (it != F[r].end()) {
            F[r].erase(it);
            fCol[j].erase(r);
          }
        } else {
          F[r][j] = sum;
          fCol[j].insert(r);
        }
      }
      for (int r : sorted(eCol[j]))
        E[r].erase(j); // exactly: E11 g = E12_j
      eCol[j].clear();
      transforms.push_back(std::move(t));
    }
    excess.clear();
    return true;
  }

  static CscMatrix toCscRows(const std::vector<SparseRow> &m,
                             const std::vector<int> &rows,
                             const std::vector<int> &colIndex, int n);

  /// Back-substitutes the pairs in [from, to), last eliminated first.
  void backSubstitute(VectorXd &x, size_t from, size_t to) const {
    for (size_t p = to; p-- > from;) {
      const Pair &pair = pairs[p];
      double pivot = 0, sum = 0;
      for (const auto &[c, v] : pair.f) {
        if (c == pair.col)
          pivot = v;
        else
          sum += v * x(c);
      }
      x(pair.col) = -sum / pivot;
    }
  }

  /// Extends a vector over the alive columns to all columns: the pairs
  /// split off after the column operations, the column operations, the
  /// pairs before them.
  VectorXd expand(const VectorXd &alive, const std::vector<int> &aliveCols) const {
    VectorXd x = VectorXd::Zero(nc);
    for (size_t k = 0; k < aliveCols.size(); ++k)
      x(aliveCols[k]) = alive(k);
    backSubstitute(x, transformAt, pairs.size());
    for (const Transform &t : transforms)
      for (const auto &[c, g] : t.g)
        x(c) -= g * x(t.col);
    backSubstitute(x, 0, transformAt);
    return x;
  }
};

CscMatrix Reducer::toCscRows(const std::vector<SparseRow> &m,
                             const std::vector<int> &rows,
                             const std::vector<int> &colIndex, int n) {
  std::vector<std::vector<std::pair<int, double>>> byCol(n);
  for (size_t r = 0; r < rows.size(); ++r)
    for (const auto &[c, v] : m[rows[r]])
      if (colIndex[c] >= 0)
        byCol[colIndex[c]].push_back({int(r), v});
  CscMatrix out;
  out.n = n;
  out.colptr.push_back(0);
  for (auto &col : byCol) {
    std::sort(col.begin(), col.end());
    for (auto &[r, v] : col) {
      out.rowind.push_back(r);
      out.values.push_back(v);
    }
    out.colptr.push_back(int(out.rowind.size()));
  }
  return out;
}

MatrixXd denseBlock(const std::vector<SparseRow> &m, const std::vector<int> &rows,
                    const std::vector<int> &colIndex, int ncols) {
  MatrixXd out = MatrixXd::Zero(rows.size(), ncols);
  for (size_t r = 0; r < rows.size(); ++r)
    for (const auto &[c, v] : m[rows[r]])
      if (colIndex[c] >= 0)
        out(r, colIndex[c]) = v;
  return out;
}

/// Rows of `m` scaled by their norms (zero rows stay zero).
MatrixXd normalizedRows(MatrixXd m) {
  for (Index i = 0; i < m.rows(); ++i) {
    double n = m.row(i).norm();
    if (n > 0)
      m.row(i) /= n;
  }
  return m;
}

/// The reduced pencil x' = A x + B z, 0 = C x of the file comment, with
/// A and B applied through E11's factorization.
struct Hessenberg {
  int r = 0, m = 0, k = 0;
  SparseLu lu;
  CscMatrix e11, f11, f11t;
  MatrixXd f12, c; // r x m, k x r (rows normalized)

  /// An orthonormal basis of E11^-1 span(q) (q orthonormal: no rank
  /// decision, E11 is nonsingular).
  MatrixXd solveOrthonormal(MatrixXd q) {
    if (q.cols() == 0 || r == 0)
      return MatrixXd(r, 0);
    for (Index j = 0; j < q.cols(); ++j)
      lu.solve(q.col(j).data());
    return Eigen::HouseholderQR<MatrixXd>(q).householderQ() *
           MatrixXd::Identity(r, q.cols());
  }
  /// Orthonormal rows spanning the rows of L E11^-1.
  MatrixXd rowsTimesInverse(const MatrixXd &l) {
    if (l.rows() == 0)
      return MatrixXd(0, r);
    return solveOrthonormalTransposed(l.transpose()).transpose();
  }
  MatrixXd solveOrthonormalTransposed(MatrixXd q) {
    for (Index j = 0; j < q.cols(); ++j)
      lu.solve(q.col(j).data(), /*transposed=*/true);
    return Eigen::HouseholderQR<MatrixXd>(q).householderQ() *
           MatrixXd::Identity(r, q.cols());
  }
  /// U F11 (rows), each row scaled by its size without cancellation.
  MatrixXd rowsTimesF11(const MatrixXd &u) {
    MatrixXd ut = u.transpose();
    return scaledColumns(sparseProduct(f11t, ut), absProduct(f11t, ut))
        .transpose();
  }
  /// U F12 with columns scaled by their size without cancellation (the
  /// left null space does not change).
  MatrixXd rowsTimesF12(const MatrixXd &u) {
    return scaledColumns(u * f12, u.cwiseAbs() * f12.cwiseAbs());
  }
  /// G = [C 0; U F11, U F12], each row scaled by its size without
  /// cancellation: V_{i+1} = ker G.
  MatrixXd constraintRows(const MatrixXd &u) {
    MatrixXd g = MatrixXd::Zero(k + u.rows(), r + m);
    g.topLeftCorner(k, r) = c;
    if (u.rows() == 0)
      return g;
    MatrixXd ut = u.transpose();
    MatrixXd left = sparseProduct(f11t, ut).transpose();
    MatrixXd leftBound = absProduct(f11t, ut).transpose();
    MatrixXd right = u * f12;
    MatrixXd rightBound = u.cwiseAbs() * f12.cwiseAbs();
    for (Index i = 0; i < u.rows(); ++i) {
      double b = std::hypot(leftBound.row(i).norm(), rightBound.row(i).norm());
      if (b == 0)
        continue;
      g.block(k + i, 0, 1, r) = left.row(i) / b;
      g.block(k + i, r, 1, m) = right.row(i) / b;
    }
    return g;
  }
};

/// The Wong sequences of the Hessenberg form; fills dims, steps and the
/// free directions (over [x; z]).
/// Steps of either sequence past which the analysis is given up: a regular
/// pencil stops after its index, and a structurally singular chain (3000
/// states, one equation missing: a mutation test) shrinks V by one
/// direction per step, each step a dense SVD, minutes in all.
constexpr int kMaxStructuredSteps = 64;

/// False: given up after kMaxStructuredSteps steps.
bool wongHessenberg(Hessenberg &h, PencilAnalysis &out, MatrixXd &free) {
  const int r = h.r, m = h.m,
            cap = std::min(r + m + 2, kMaxStructuredSteps);
  // V: V_{i+1} = ker G_i, G_i = [C 0; U_i F11, U_i F12] with U_i = L_i
  // E11^-1 and L_i the annihilator of X_i = P_x V_i (L_0 empty).
  MatrixXd U(0, r), G;
  int dimPrev = r + m;
  for (int i = 0; i < cap; ++i) {
    MatrixXd g = h.constraintRows(U);
    int dim = r + m - int(orthColumns(g.transpose()).cols());
    G = std::move(g);
    if (dim == dimPrev) {
      out.stepsV = i;
      break;
    }
    dimPrev = dim;
    if (i + 1 == cap)
      return false;
    // L_{i+1}: C and the rows of U_i F11 that U_i F12 leaves free.
    MatrixXd stacked = h.c;
    if (U.rows()) {
      MatrixXd N = leftNullRows(h.rowsTimesF12(U));
      if (N.rows()) {
        stacked.conservativeResize(h.k + N.rows(), r);
        stacked.bottomRows(N.rows()) = h.rowsTimesF11(N * U);
      }
    }
    MatrixXd L = orthColumns(stacked.transpose()).transpose();
    U = h.rowsTimesInverse(L);
  }
  out.dimV = dimPrev;
  // T: T_0 = 0, T_1 = 0 x R^m, T_{i+1} = Y_i x R^m with
  // Y_i = E11^-1 [F11 (Y_{i-1} ∩ ker C), F12].
  MatrixXd Y(r, 0);
  out.stepsW = 0;
  out.dimW = 0;
  if (m > 0) {
    int prev = m; // dim T_1
    for (int i = 1; i < cap; ++i) {
      MatrixXd kerC = Y.cols() ? MatrixXd(Y * nullBasis(h.c * Y, kBasisTol))
                               : MatrixXd(r, 0);
      MatrixXd g(r, kerC.cols() + m);
      g << scaledColumns(sparseProduct(h.f11, kerC), absProduct(h.f11, kerC)),
          scaledColumns(h.f12, h.f12.cwiseAbs());
      Y = h.solveOrthonormal(orthColumns(g));
      int dim = int(Y.cols()) + m;
      if (dim == prev) {
        out.stepsW = i;
        break;
      }
      prev = dim;
      if (i + 1 == cap)
        return false;
    }
    out.dimW = prev;
  }
  // V ∩ T: the (Y a, z) in ker G.
  if (m == 0) {
    free = MatrixXd(r + m, 0);
    return true;
  }
  MatrixXd ym = MatrixXd::Zero(r + m, Y.cols() + m);
  ym.topLeftCorner(r, Y.cols()) = Y;
  ym.bottomRightCorner(m, m) = MatrixXd::Identity(m, m);
  const MatrixXd n = nullBasis(G * ym, kBasisTol);
  // ym * n without multiplying by ym's identity block: m may be thousands.
  free.resize(r + m, n.cols());
  free.topRows(r) = Y * n.topRows(Y.cols());
  free.bottomRows(m) = n.bottomRows(m);
  return true;
}

void denseOn(const MatrixXd &E, const MatrixXd &F, double tol,
             PencilAnalysis &out, MatrixXd &free) {
  WongResult w = wongSequences(E, F, tol);
  out.dimV = int(w.V.cols());
  out.dimW = int(w.T.cols());
  out.stepsV = w.stepsV;
  out.stepsW = w.stepsT;
  free = intersect(w.V, w.T, kBasisTol);
}

} // namespace

/// Columns no entry reads are free directions of their own (e_c is in
/// both V and W): analyzed apart, so that what is left stays the size of
/// the equations, not of the unknowns. Null when every column is read.
static std::optional<PencilAnalysis> withUnusedColumns(const SparsePencil &p,
                                                const PencilOptions &opts) {
  std::vector<int> index(p.cols, -1);
  for (const auto *list : {&p.E, &p.F})
    for (const SparsePencil::Entry &e : *list)
      index[e.col] = 0;
  std::vector<int> unused;
  SparsePencil sub;
  sub.rows = p.rows;
  for (int c = 0; c < p.cols; ++c)
    if (index[c] < 0)
      unused.push_back(c);
    else
      index[c] = sub.cols++;
  if (unused.empty())
    return std::nullopt;
  for (const SparsePencil::Entry &e : p.E)
    sub.E.push_back({e.row, index[e.col], e.value});
  for (const SparsePencil::Entry &e : p.F)
    sub.F.push_back({e.row, index[e.col], e.value});
  PencilAnalysis out = analyzePencil(sub, opts);
  out.square = p.rows == p.cols;
  if (!out.computed)
    return out;
  const Index kept = std::min<Index>(Index(unused.size()), kMaxUnitDirections);
  MatrixXd free = MatrixXd::Zero(p.cols, out.freeDirections.cols() + kept);
  for (int c = 0; c < p.cols; ++c)
    if (index[c] >= 0 && index[c] < out.freeDirections.rows())
      free.row(c).head(out.freeDirections.cols()) =
          out.freeDirections.row(index[c]);
  for (Index k = 0; k < kept; ++k)
    free(unused[size_t(k)], out.freeDirections.cols() + k) = 1;
  out.freeCount += Index(unused.size());
  out.freeDirections = std::move(free);
  out.dimV += int(unused.size());
  out.dimW += int(unused.size());
  out.regular = false;
  return out;
}

PencilAnalysis analyzePencil(const SparsePencil &p, const PencilOptions &opts) {
  if (std::optional<PencilAnalysis> split = withUnusedColumns(p, opts))
    return *split;
  PencilAnalysis out;
  out.square = p.rows == p.cols;
  MatrixXd free;
  if (p.cols <= opts.denseLimit) {
    MatrixXd E, F;
    densePencil(p, E, F);
    denseOn(E, F, opts.tol, out, free);
    out.path = "dense";
    out.reducedRows = p.rows;
    out.reducedCols = p.cols;
    out.computed = true;
    out.freeDirections = free;
    out.freeCount = free.cols();
    out.regular = out.square && out.dimV + out.dimW == p.cols &&
                  free.cols() == 0;
    return out;
  }

  Reducer red(p, opts.tol);
  red.splitIndexOnePairs();
  red.compressE();
  red.excessColumn = !red.clearExcessColumns();
  red.splitIndexOnePairs();

  std::vector<int> rows1, rowsC, colsD, colsA;
  for (int i = 0; i < p.rows; ++i)
    if (red.rowAlive[i])
      (red.E[i].empty() ? rowsC : rows1).push_back(i);
  for (int c = 0; c < p.cols; ++c)
    if (red.colAlive[c])
      (red.eCol[c].empty() ? colsA : colsD).push_back(c);
  out.indexOnePairs = int(red.pairs.size());
  out.reducedRows = int(rows1.size() + rowsC.size());
  out.reducedCols = int(colsD.size() + colsA.size());
  std::vector<int> aliveCols = colsD;
  aliveCols.insert(aliveCols.end(), colsA.begin(), colsA.end());

  bool structured = !red.excessColumn && rows1.size() == colsD.size();
  Hessenberg h;
  if (structured) {
    h.r = int(colsD.size());
    h.m = int(colsA.size());
    h.k = int(rowsC.size());
    std::vector<int> dIndex(p.cols, -1), aIndex(p.cols, -1);
    for (size_t k = 0; k < colsD.size(); ++k)
      dIndex[colsD[k]] = int(k);
    for (size_t k = 0; k < colsA.size(); ++k)
      aIndex[colsA[k]] = int(k);
    h.e11 = Reducer::toCscRows(red.E, rows1, dIndex, h.r);
    h.f11 = Reducer::toCscRows(red.F, rows1, dIndex, h.r);
    h.f11t = h.f11.transposed();
    h.f12 = denseBlock(red.F, rows1, aIndex, h.m);
    h.c = normalizedRows(denseBlock(red.F, rowsC, dIndex, h.r));
    structured = h.r == 0 || (h.lu.factor(h.e11) &&
                              h.lu.rcondEstimate() > opts.tol);
  }
  if (structured) {
    if (!wongHessenberg(h, out, free)) {
      out.path = "too many steps";
      return out;
    }
    out.path = "structured";
  } else if (out.reducedCols <= opts.denseFallbackLimit &&
             out.reducedRows <= opts.denseFallbackLimit) {
    std::vector<int> allRows = rows1;
    allRows.insert(allRows.end(), rowsC.begin(), rowsC.end());
    std::vector<int> colIndex(p.cols, -1);
    for (size_t k = 0; k < aliveCols.size(); ++k)
      colIndex[aliveCols[k]] = int(k);
    MatrixXd E = denseBlock(red.E, allRows, colIndex, out.reducedCols);
    MatrixXd F = denseBlock(red.F, allRows, colIndex, out.reducedCols);
    denseOn(E, F, opts.tol, out, free);
    out.path = "reduced-dense";
  } else {
    out.path = "too large";
    return out;
  }
  out.computed = true;
  // The index-1 pairs: (0, f) blocks, T += 1 each, one W-step.
  out.dimW += out.indexOnePairs;
  if (out.indexOnePairs > 0) {
    out.stepsW = std::max(out.stepsW, 1);
    out.stepsV = std::max(out.stepsV, 1);
  }
  MatrixXd full(p.cols, free.cols());
  for (Index j = 0; j < free.cols(); ++j)
    full.col(j) = red.expand(free.col(j), aliveCols);
  // Orthonormalized by an SVD while that is cheap; past kOrthLimit free
  // directions (one equation for 3000 unknowns) the expanded basis is kept
  // as it is: its columns are independent already, and an SVD of it would
  // take minutes.
  constexpr Index kOrthLimit = 400;
  out.freeDirections = free.cols() == 0         ? MatrixXd(p.cols, 0)
                       : free.cols() > kOrthLimit ? full
                                                  : orthColumns(full);
  out.freeCount = out.freeDirections.cols();
  out.regular = out.square && out.dimV + out.dimW == p.cols &&
                out.freeDirections.cols() == 0;
  return out;
}

} // namespace ldae::numeric
