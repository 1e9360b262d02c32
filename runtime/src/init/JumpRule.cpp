// The jump directions of the pencil as written (see JumpRule.h).
#include "init/JumpRule.h"
#include "numeric/WongSequence.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ldae::runtime {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

/// Rank tolerance of the Wong sequences (relative, on the row-equilibrated
/// pencil).
constexpr double kWongTol = 1e-10;

const int *dummyRow(const ldae_model &m, int set) {
  return m.dummy_of ? m.dummy_of[set] : nullptr;
}
const int *originalRow(const ldae_model &m, int set) {
  return m.original_row ? m.original_row[set] : nullptr;
}

/// Each row of the pencil divided by its largest entry in E or F: T is
/// unchanged, and a capacitance of 1e-9 in one row must not look like zero
/// beside a conductance in another. Then E as a whole scaled to F's
/// largest entry (T of (aE, F) is T of (E, F): a change of the time unit):
/// the rank tolerance is relative to the larger of the two, and a circuit
/// whose time constants are all short (MSL's SimpleTriacCircuit: L/R =
/// 2e-7 s, a thyristor's 1e-6 s) had E x below it for a differential
/// direction x the algebraic equations do not reach, which the sequence
/// then took into T (index 2 for an index-1 set).
void equilibrateRows(MatrixXd &E, MatrixXd &F) {
  for (Eigen::Index a = 0; a < E.rows(); ++a) {
    double s = std::max(E.row(a).cwiseAbs().maxCoeff(),
                        F.row(a).cwiseAbs().maxCoeff());
    if (s > 0) {
      E.row(a) /= s;
      F.row(a) /= s;
    }
  }
  if (E.size() == 0)
    return;
  double e = E.cwiseAbs().maxCoeff(), f = F.cwiseAbs().maxCoeff();
  if (e > 0 && f > 0)
    E *= f / e;
}

/// The pencil as written in scaled coordinates; `cols` are its unknowns.
/// False when an equation as written reads a dummy that stands for the
/// derivative of another dummy (a second derivative: the pencil is not
/// first order over the non-dummy unknowns).
bool writtenPencil(const ldae_model &m, int set, const MatrixXd &E,
                   const MatrixXd &Fy, const VectorXd &D, MatrixXd &Ew,
                   MatrixXd &Fw, std::vector<int> &cols) {
  const int n = m.n;
  const int *dummy = dummyRow(m, set);
  const int *orig = originalRow(m, set);
  std::vector<int> colOf(n, -1), rows;
  cols.clear();
  for (int j = 0; j < n; ++j)
    if (!dummy || dummy[j] < 0) {
      colOf[j] = int(cols.size());
      cols.push_back(j);
    }
  for (int r = 0; r < n; ++r)
    if (!orig || orig[r])
      rows.push_back(r);
  Ew = MatrixXd::Zero(rows.size(), cols.size());
  Fw = MatrixXd::Zero(rows.size(), cols.size());
  for (size_t a = 0; a < rows.size(); ++a) {
    int r = rows[a];
    for (size_t c = 0; c < cols.size(); ++c) {
      Ew(a, c) = E(r, cols[c]);
      Fw(a, c) = -Fy(r, cols[c]);
    }
    if (!dummy)
      continue;
    for (int d = 0; d < n; ++d) {
      if (dummy[d] < 0 || Fy(r, d) == 0)
        continue;
      int j = dummy[d];
      if (j >= n || colOf[j] < 0)
        return false;
      Ew(a, colOf[j]) += Fy(r, d);
    }
  }
  // Nominal scaling of the columns, then each row equilibrated: both leave
  // T unchanged (up to the column scaling), and a capacitance of 1e-9 in
  // one row must not look like zero beside a conductance in another.
  for (size_t c = 0; c < cols.size(); ++c) {
    Ew.col(c) *= D(cols[c]);
    Fw.col(c) *= D(cols[c]);
  }
  equilibrateRows(Ew, Fw);
  return true;
}

} // namespace

MatrixXd writtenJumpBasis(const ModelEval &ev, double t, const double *y,
                          const double *yp, const std::vector<int> &held) {
  const ldae_model &m = ev.model();
  MatrixXd Fy, E;
  if (m.n_written <= 0 || m.n > kJumpRuleDenseLimit ||
      ev.writtenJacobian(t, y, yp, Fy, E) != 0 || !Fy.allFinite() ||
      !E.allFinite())
    return MatrixXd();
  const VectorXd D = nominalScale(m);
  MatrixXd Ew = E * D.asDiagonal(), Fw = -Fy * D.asDiagonal();
  equilibrateRows(Ew, Fw);
  int index = 0;
  MatrixXd T = D.asDiagonal() * numeric::jumpSpace(Ew, Fw, &index, kWongTol);
  if (held.empty() || T.cols() == 0)
    return T;
  MatrixXd Th(held.size(), T.cols());
  for (size_t r = 0; r < held.size(); ++r)
    Th.row(Eigen::Index(r)) = T.row(held[r]);
  Eigen::FullPivLU<MatrixXd> lu(Th);
  lu.setThreshold(kWongTol);
  if (lu.rank() == Th.cols())
    return MatrixXd(m.n, 0); // (kernel() is one zero column then)
  return T * lu.kernel();
}

bool hasWrittenPencil(const ldae_model &m, int set) {
  const int *dummy = dummyRow(m, set);
  const int *orig = originalRow(m, set);
  for (int i = 0; i < m.n; ++i)
    if ((dummy && dummy[i] >= 0) || (orig && !orig[i]))
      return true;
  return false;
}

JumpDirections jumpDirections(const ldae_model &m, int set, const MatrixXd &E,
                              const MatrixXd &Fy, const VectorXd &D) {
  JumpDirections jd;
  const int n = m.n;
  // The set's own pencil equilibrated as the written one: a rectifier's
  // reduced row divided by an inductance (1/L = 2e4) beside rows of a
  // diode's off conductance (1e-3) made the absolute rank tolerance call
  // the index-1 set index 2 (MSL's Analog.Examples.Rectifier).
  MatrixXd Es = E * D.asDiagonal(), Fs = -Fy * D.asDiagonal();
  equilibrateRows(Es, Fs);
  MatrixXd own = numeric::jumpSpace(Es, Fs, &jd.setIndex, kWongTol);
  auto useOwn = [&] {
    jd.basis = std::move(own);
    jd.dim = int(jd.basis.cols());
    jd.index = jd.setIndex;
    return jd;
  };
  if (!hasWrittenPencil(m, set))
    return useOwn();
  if (n > kJumpRuleDenseLimit) {
    jd.fallback = "the pencil as written is dense and the model is too large";
    return useOwn();
  }
  MatrixXd Ew, Fw;
  std::vector<int> cols;
  if (!writtenPencil(m, set, E, Fy, D, Ew, Fw, cols)) {
    jd.fallback = "an equation as written reads a second derivative";
    return useOwn();
  }
  MatrixXd T = numeric::jumpSpace(Ew, Fw, &jd.index, kWongTol);
  jd.written = true;
  jd.dim = int(T.cols());
  jd.dummies = n - int(cols.size());
  jd.basis = MatrixXd::Zero(n, jd.dim + jd.dummies);
  for (size_t c = 0; c < cols.size(); ++c)
    jd.basis.row(cols[c]).head(jd.dim) = T.row(c);
  int k = jd.dim;
  for (int j = 0, c = 0; j < n; ++j)
    if (c < int(cols.size()) && cols[c] == j)
      ++c;
    else
      jd.basis(j, k++) = 1;
  return jd;
}

bool jumpsAreAlgebraic(const ldae_model &m, int set,
                       const JumpDirections &jd) {
  const int *diff = m.state_sets[set].is_differential;
  int algebraic = 0;
  for (int j = 0; j < m.n; ++j) {
    if (!diff[j]) {
      ++algebraic;
      continue;
    }
    if (jd.basis.cols() && jd.basis.row(j).cwiseAbs().maxCoeff() > 1e-10)
      return false;
  }
  return algebraic == jd.basis.cols();
}

VectorXd nominalScale(const ldae_model &m) {
  VectorXd D = VectorXd::Ones(m.n);
  if (m.nominal)
    for (int i = 0; i < m.n; ++i)
      D(i) = m.nominal[i];
  return D;
}

bool jumpRuleKeepsStates(const ModelEval &ev, int set, double t,
                         const double *y, const double *yp) {
  const ldae_model &m = ev.model();
  if (!hasWrittenPencil(m, set) || ev.n() > kJumpRuleDenseLimit)
    return true;
  MatrixXd Fy, E;
  if (ev.jacobianParts(set, t, y, yp, Fy, E) != 0)
    return false;
  return jumpsAreAlgebraic(m, set,
                           jumpDirections(m, set, E, Fy, nominalScale(m)));
}

} // namespace ldae::runtime
