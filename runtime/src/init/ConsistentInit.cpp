// Consistent initialization along the jump space (see ConsistentInit.h).
//
// One Newton step at the iterate (y, y'): with D = diag(nominal) the
// unknowns are scaled (y = D u), the pencil is (E D, -F_y D), T the jump
// space of the model as written (JumpRule.h; with every dummy coordinate),
// B an orthonormal basis of the allowed directions (T with the held
// coordinates held; plus the free differential coordinates when initial
// equations need them). The step solves, in the least-squares minimum-norm
// sense,
//   F + F_y D B a + E D du'           = 0   (the equations)
//   F_y (y' + D du') + E D z_2 + F_t  = 0   (their time derivative, and so
//   F_y D z_j + E D z_{j+1}           = 0    on, index - 1 levels: the hidden
//                                            constraints of a higher index)
//   G + G_y D B a + G_y' D du'        = 0   (initial equations)
// so the start vector moves only along T, by the smallest step in the
// nominal-scaled norm within T.
#include "init/ConsistentInit.h"
#include "init/JumpRule.h"
#include "init/SparseInit.h"
#include "numeric/NewtonKernel.h"
#include "numeric/Rank.h"
#include "numeric/WongSequence.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <ostream>

namespace ldae::runtime {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

/// Rank threshold of the index-1 test, relative to the largest pivot
/// (dense) or as the reciprocal 1-norm condition estimate (sparse).
constexpr double kIndexOneRankTol = 1e-12;

/// Whether the conditions leave the differential values alone: no initial
/// equations, no held algebraic unknown.
bool conditionsAllowIndexOne(const ModelEval &ev, int set,
                             const InitConditions &c) {
  if (c.numInitial(ev.model()) > 0)
    return false;
  for (int i = 0; i < ev.n(); ++i)
    if (!ev.set(set).is_differential[i] && c.isHeld(i))
      return false;
  return true;
}


bool isPlainIndexOneDense(const ModelEval &ev, int set, double t,
                          const double *y, const double *yp) {
  const ldae_model &m = ev.model();
  const ldae_state_set &s = ev.set(set);
  int n = ev.n();
  MatrixXd Fy, E;
  if (ev.jacobianParts(set, t, y, yp, Fy, E) != 0)
    return false;
  // E must vanish on the algebraic columns; [E_d F_a] must be nonsingular.
  MatrixXd M(n, n);
  double scale = std::max(
      {1e-300, E.cwiseAbs().maxCoeff(), n ? Fy.cwiseAbs().maxCoeff() : 0.0});
  for (int j = 0; j < n; ++j) {
    const double *nom = m.nominal;
    double d = nom ? nom[j] : 1.0;
    if (s.is_differential[j]) {
      M.col(j) = E.col(j) * d;
    } else {
      if (E.col(j).cwiseAbs().maxCoeff() > 1e-14 * scale)
        return false;
      M.col(j) = Fy.col(j) * d;
    }
  }
  // A rank-revealing LU: an order of magnitude cheaper than an SVD, which
  // dominated start-up for models of a few hundred unknowns.
  return numeric::isNonsingular(M, kIndexOneRankTol);
}

/// The nominal-scaled index-1 iteration matrix M = [E_d D_d, F_a D_a]
/// (differential columns from E, algebraic ones from F_y) in the shared
/// pattern of Fy and E. False when E does not vanish on an algebraic
/// column (relative to the largest entry of either): not index 1 in this
/// form.
bool indexOneMatrix(const ModelEval &ev, int set, const CscMatrix &Fy,
                    const CscMatrix &E, CscMatrix &M) {
  const ldae_model &m = ev.model();
  const int *diff = ev.set(set).is_differential;
  double scale = std::max({1e-300, E.maxAbs(), Fy.maxAbs()});
  M = Fy;
  for (int j = 0; j < M.n; ++j) {
    double d = m.nominal ? m.nominal[j] : 1.0;
    for (int q = M.colptr[j]; q < M.colptr[j + 1]; ++q) {
      if (diff[j]) {
        M.values[q] = E.values[q] * d;
        continue;
      }
      if (std::fabs(E.values[q]) > 1e-14 * scale)
        return false;
      M.values[q] *= d;
    }
  }
  return true;
}

/// Largest |entry| of each row of M, floored at 1e-8 max(1, max |M|): a
/// residual is judged relative to its row's sensitivity to the scaled
/// unknowns (as in the dense Newton below), and a row whose coefficients
/// are round-off must not turn round-off residuals into large ones.
std::vector<double> rowScales(const CscMatrix &M) {
  std::vector<double> s(M.n, 0.0);
  for (int q = 0; q < M.nnz(); ++q)
    s[M.rowind[q]] = std::max(s[M.rowind[q]], std::fabs(M.values[q]));
  double floor = 1e-8 * std::max(1.0, M.maxAbs());
  for (double &v : s)
    v = std::max(v, floor);
  return s;
}

bool isPlainIndexOneSparse(const ModelEval &ev, int set, double t,
                           const double *y, const double *yp) {
  CscMatrix Fy, E, M;
  if (ev.jacobianPartsCsc(set, t, y, yp, Fy, E) != 0 ||
      !indexOneMatrix(ev, set, Fy, E, M))
    return false;
  // Equations in other units must not decide the rank: equilibrate the
  // rows, then ask KLU for a factorization without a zero pivot and a
  // condition estimate within the dense test's rank threshold.
  std::vector<double> rs = rowScales(M);
  for (int q = 0; q < M.nnz(); ++q)
    M.values[q] /= rs[M.rowind[q]];
  SparseLu lu;
  return lu.factor(M) && lu.rcondEstimate() >= kIndexOneRankTol;
}

/// The common failure message when no consistent point was found.
std::string noConsistentPoint(const std::string &rows, double best) {
  return fmt::format(
      "no consistent initial point: {} cannot be met (smallest residual "
      "reached {:.3g}); check the start values, fixed values and initial "
      "equations",
      rows.empty() ? std::string("the equations") : rows, best);
}

/// The unknowns residual rows `rows` read whose start values are guesses
/// (not held): "; iteration variables 'x' (guess 0, reached 0.816); give
/// start values near the solution for 'x'", or "" when there are none.
std::string guessesOf(const ModelEval &ev, int set, const InitConditions &cond,
                      const std::vector<int> &rows,
                      const std::vector<double> &y0, const VectorXd &y) {
  const ldae_state_set &s = ev.set(set);
  std::vector<char> bad(ev.n(), 0);
  for (int r : rows)
    if (r >= 0 && r < ev.n())
      bad[r] = 1;
  std::vector<std::string> vars, names;
  for (int c = 0; c < ev.n() && vars.size() < 5; ++c) {
    if (cond.isHeld(c) || s.is_differential[c])
      continue;
    // A model with only a dense Jacobian has no pattern: any row may read
    // the column.
    bool reads = !s.jac_colptr;
    if (s.jac_colptr)
      for (int q = s.jac_colptr[c]; q < s.jac_colptr[c + 1] && !reads; ++q)
        reads = bad[s.jac_rowind[q]];
    if (!reads)
      continue;
    vars.push_back(fmt::format("'{}' (guess {:.6g}, reached {:.6g})",
                               ev.varName(c), y0[c], y(c)));
    names.push_back(fmt::format("'{}'", ev.varName(c)));
  }
  if (vars.empty())
    return "";
  return fmt::format("; iteration variables {}; give start values near the "
                     "solution for {}",
                     fmt::join(vars, ", "), fmt::join(names, ", "));
}

std::string domainFailure(const std::string &what) {
  return fmt::format("{} is outside its domain at the start values", what);
}

} // namespace

bool usesSparseInit(const ModelEval &ev) {
  return ev.n() > LDAE_DENSE_THRESHOLD;
}

bool isPlainIndexOne(const ModelEval &ev, int set, double t, const double *y,
                     const double *yp) {
  return isPlainIndexOne(ev, set, t, y, yp,
                         InitConditions::atStart(ev.model()));
}

bool isPlainIndexOne(const ModelEval &ev, int set, double t, const double *y,
                     const double *yp, const InitConditions &c) {
  if (!conditionsAllowIndexOne(ev, set, c))
    return false;
  bool plain = usesSparseInit(ev) ? isPlainIndexOneSparse(ev, set, t, y, yp)
                                  : isPlainIndexOneDense(ev, set, t, y, yp);
  return plain && jumpRuleKeepsStates(ev, set, t, y, yp);
}

InitOutcome initializeIndexOne(const ModelEval &ev, int set, double t,
                               const std::vector<double> &y0,
                               const std::vector<double> &yp0) {
  // With no conditions every differential value gets a keep row, and the
  // sparse initialization's system is M (dy_a, dy'_d) = -F exactly.
  return initializeSparse(ev, set, t, y0, yp0);
}

namespace {

enum class Mode { Jumps, Nearest };

/// The convergence tolerance of residuals (row-scaled, nominal units) and
/// steps.
constexpr double kTol = 1e-10;

/// Entries of an orthonormal direction basis below this are round-off.
constexpr double kBasisRoundOff = 1e-12;

struct StepResult {
  bool solvable = true; // the linearized conditions have a solution
  bool converged = false;
  double residual = 0; // max scaled residual before the step
  std::vector<int> badRows;
  int jumpDim = 0, index = 0, levels = 0;
  bool written = false; // T of the model as written
  std::string domainError;
  int domainRow = -1; // residual row of the domain error, if one
};

class Newton {
public:
  Newton(const ModelEval &ev, int set, double t, const InitConditions &c)
      : ev_(ev), m_(ev.model()), c_(c), set_(set), t_(t), n_(ev.n()),
        D_(nominalScale(ev.model())) {}

  /// The residuals and Jacobians at (y, y'); false with the domain error
  /// in `res`.
  bool evaluate(const VectorXd &y, const VectorXd &yp, StepResult &res) {
    int ni = c_.numInitial(m_);
    r.resize(n_);
    g.resize(ni);
    Gy.resize(ni, n_);
    Gyp.resize(ni, n_);
    if (int rc = ev_.residual(set_, t_, y.data(), yp.data(), r.data())) {
      res.domainError = rc > 0 ? ev_.describeRow(rc - 1) : "the residual";
      res.domainRow = rc - 1;
      return false;
    }
    if (int rc = ev_.jacobianParts(set_, t_, y.data(), yp.data(), Fy, E)) {
      res.domainError = rc > 0 ? ev_.describeRow(rc - 1) : "the Jacobian";
      res.domainRow = rc - 1;
      return false;
    }
    if (ni > 0) {
      if (ev_.initResidual(t_, y.data(), yp.data(), g.data()) ||
          ev_.initJacobian(t_, y.data(), yp.data(), Gy, Gyp)) {
        res.domainError = "an initial equation";
        return false;
      }
    }
    return true;
  }

  /// The step from the last evaluation, its residual and solvability in
  /// `res`.
  void solve(Mode mode, const VectorXd &y, const VectorXd &yp,
             StepResult &res) {
    int ni = c_.numInitial(m_);
    VectorXd rt(n_);
    MatrixXd Es = E * D_.asDiagonal(), Fs = Fy * D_.asDiagonal();
    JumpDirections jd = jumpDirections(m_, set_, E, Fy, D_);
    const MatrixXd &T = jd.basis;
    res.index = jd.index;
    res.written = jd.written;
    // The set's own hidden constraints (the reduced set is index 1 unless
    // it is the model as written of a higher index).
    int levels = std::max(jd.setIndex - 1, 0);

    // Free coordinates: every unknown whose value is not held.
    std::vector<int> freeIdx, freeDiff;
    for (int i = 0; i < n_; ++i)
      if (!c_.isHeld(i)) {
        freeIdx.push_back(i);
        if (ev_.set(set_).is_differential[i])
          freeDiff.push_back(i);
      }
    MatrixXd U = MatrixXd::Zero(n_, freeIdx.size());
    for (size_t c = 0; c < freeIdx.size(); ++c)
      U(freeIdx[c], c) = 1;
    MatrixXd B;
    if (mode == Mode::Jumps) {
      B = numeric::intersect(T, U, 1e-10);
      if (ni > 0 && !freeDiff.empty()) {
        // Initial equations may tie differential values too; those move
        // as little as the equations allow.
        MatrixXd Bd(n_, B.cols() + freeDiff.size());
        Bd.leftCols(B.cols()) = B;
        Bd.rightCols(freeDiff.size()).setZero();
        for (size_t c = 0; c < freeDiff.size(); ++c)
          Bd(freeDiff[c], B.cols() + c) = 1;
        B = numeric::rangeBasis(Bd, 1e-10);
      }
      // The SVDs leave round-off (1e-16) on coordinates the directions do
      // not touch, held ones included; a row that only such coordinates
      // could change would then look reachable and its round-off residual
      // unsolvable (the pendulum with x and vx fixed). Exact zeros there.
      for (int i = 0; i < n_; ++i)
        for (Eigen::Index c = 0; c < B.cols(); ++c)
          if (c_.isHeld(i) || std::fabs(B(i, c)) < kBasisRoundOff)
            B(i, c) = 0;
    } else {
      B = U;
    }
    // Dummies are never held: every one stays in B, and is no jump.
    res.jumpDim = int(B.cols()) - (mode == Mode::Jumps ? jd.dummies : 0);

    if (levels > 0) {
      // F_t by a forward difference: the hidden constraints of a
      // time-dependent model carry it.
      double h = 1e-7 * std::max(1.0, std::fabs(t_));
      VectorXd r1(n_);
      if (ev_.residual(set_, t_ + h, y.data(), yp.data(), r1.data()) == 0)
        rt = (r1 - r) / h;
      else
        rt.setZero();
    }

    int k = B.cols();
    int cols = k + n_ * (1 + levels), rows = n_ * (1 + levels) + ni;
    MatrixXd A = MatrixXd::Zero(rows, cols);
    VectorXd b = VectorXd::Zero(rows);
    A.block(0, 0, n_, k) = Fs * B;
    A.block(0, k, n_, n_) = Es;
    b.head(n_) = -r;
    for (int l = 1; l <= levels; ++l) {
      int row = n_ * l, col = k + n_ * (l - 1);
      A.block(row, col, n_, n_) = Fs;
      A.block(row, col + n_, n_, n_) = Es;
      if (l == 1)
        b.segment(row, n_) = -(Fy * yp + rt);
    }
    if (ni > 0) {
      int row = n_ * (1 + levels);
      A.block(row, 0, ni, k) = Gy * D_.asDiagonal() * B;
      A.block(row, k, ni, n_) = Gyp * D_.asDiagonal();
      b.tail(ni) = -g;
    }
    // Residuals are judged relative to their row's sensitivity to the
    // scaled unknowns: "how far off, in nominal units". Only the equations
    // themselves (level 0) and the initial equations have a residual of the
    // state; the derivative levels constrain the step (their unknowns z_j
    // are solved afresh each time).
    // (Floored relative to the whole matrix: a row whose coefficients are
    // round-off must not turn round-off residuals into large ones.)
    VectorXd rowScale(rows);
    double floor = 1e-8 * std::max(1.0, A.cwiseAbs().maxCoeff());
    for (int i = 0; i < rows; ++i)
      rowScale(i) = std::max(A.row(i).cwiseAbs().maxCoeff(), floor);
    VectorXd scaled = b.cwiseAbs().cwiseQuotient(rowScale);
    auto isStateRow = [&](int i) { return i < n_ || i >= n_ * (1 + levels); };
    res.residual = 0;
    for (int i = 0; i < rows; ++i)
      if (isStateRow(i)) {
        res.residual = std::max(res.residual, scaled(i));
        if (scaled(i) > kTol)
          res.badRows.push_back(i);
      }
    // Solved with the rows in the same units: the rank threshold is
    // relative to the largest singular value, and a thyristor's off law
    // (i = vAK/Roff: 1e-6 per volt) beside its control lag (2.5/1.87e-6 =
    // 1.3e6 per volt) fell below it, the equation left unsolved and no
    // consistent point found for an index-1 set (MSL's
    // ThyristorBehaviourTest after its gate pulse). Row scaling leaves the
    // solutions of a consistent system as they are.
    MatrixXd As = rowScale.cwiseInverse().asDiagonal() * A;
    VectorXd bs = b.cwiseQuotient(rowScale);
    // The derivative columns (du' and the levels' z_j, from k on) are
    // solved in their own units too, each divided by its largest entry. A
    // derivative's coefficient is a time constant (C in i = C*der(v), in
    // seconds per unit of the row), 1e-13 for a small capacitance against
    // 1 for the current: the column fell below the rank threshold, the
    // row it alone can meet was left unsolved and no consistent point
    // found (MSL's OpAmpDetailed, Cin = 1.4e-12 F;
    // tests/lang/init/tiny_capacitance.lsd). Column scaling changes only
    // how the minimum norm weighs the derivatives, which have no start
    // value to stay near; the directions' columns (B's, up to k) keep
    // their nominal weights, so the step in y stays the smallest one along
    // T.
    VectorXd cs = VectorXd::Ones(cols);
    for (int c = k; c < cols; ++c)
      if (double big = As.col(c).cwiseAbs().maxCoeff(); big > 0)
        cs(c) = big;
    MatrixXd Ac = As * cs.cwiseInverse().asDiagonal();
    VectorXd x = numeric::minimumNormSolution(Ac, bs, 1e-12).cwiseQuotient(cs);
    VectorXd lin = (As * x - bs).cwiseAbs();
    if (lin.maxCoeff() > 1e-8 * std::max(1.0, scaled.maxCoeff())) {
      res.solvable = false;
      res.badRows.clear();
      for (int i = 0; i < rows; ++i)
        if (lin(i) > 1e-8 * std::max(1.0, scaled.maxCoeff()))
          res.badRows.push_back(i);
    }
    dy_ = B * x.head(k);
    dyp_ = x.segment(k, n_);
    res.levels = levels;
  }

  /// Takes the step solved for; fills the result's convergence status.
  void apply(VectorXd &y, VectorXd &yp, StepResult &res) const {
    y += D_.asDiagonal() * dy_;
    yp += D_.asDiagonal() * dyp_;
    // Converged: the equations hold and the hidden constraints (through
    // the derivative levels) ask for no further move along T.
    res.converged = res.solvable && res.badRows.empty() &&
                    (dy_.size() == 0 || dy_.cwiseAbs().maxCoeff() <= kTol);
  }

  /// "equation 3 at model.lsd:12" for a row of the step's system.
  std::string describe(int row, int levels) const {
    int level = row / n_;
    if (row >= n_ * (1 + levels))
      return fmt::format("initial equation {}", row - n_ * (1 + levels) + 1);
    std::string what = ev_.describeRow(row % n_);
    return level == 0
               ? what
               : fmt::format("the time derivative ({}) of {}", level, what);
  }

private:
  const ModelEval &ev_;
  const ldae_model &m_;
  const InitConditions &c_;
  int set_;
  double t_;
  int n_;
  VectorXd D_;
  /// The last evaluation.
  VectorXd r, g;
  MatrixXd Fy, E, Gy, Gyp;
  /// The last step solved for (nominal-scaled).
  VectorXd dy_, dyp_;
};

} // namespace

InitOutcome initializeAlongJumps(const ModelEval &ev, int set, double t,
                                 const std::vector<double> &y0,
                                 const std::vector<double> &yp0,
                                 std::ostream *log) {
  return initializeAlongJumps(ev, set, t, y0, yp0,
                              InitConditions::atStart(ev.model()), log);
}

InitOutcome initializeAlongJumps(const ModelEval &ev, int set, double t,
                                 const std::vector<double> &y0,
                                 const std::vector<double> &yp0,
                                 const InitConditions &c, std::ostream *log) {
  InitOutcome out;
  Newton newton(ev, set, t, c);
  int n = ev.n();
  double best = INFINITY;
  StepResult last;
  VectorXd reached;
  for (Mode mode : {Mode::Jumps, Mode::Nearest}) {
    VectorXd y = Eigen::Map<const VectorXd>(y0.data(), n);
    VectorXd yp = Eigen::Map<const VectorXd>(yp0.data(), n);
    // The Newton iteration in `mode`: stops where the linearized
    // conditions have no solution along T (the nearest point next).
    struct Steps : numeric::NewtonSystem {
      Steps(Newton &newton, Mode mode, VectorXd &y, VectorXd &yp,
            InitOutcome &out, double &best, StepResult &last)
          : newton(newton), mode(mode), y(y), yp(yp), out(out), best(best),
            last(last) {}
      bool evaluate(int) override {
        s = StepResult();
        if (newton.evaluate(y, yp, s))
          return true;
        noteFirst();
        return false;
      }
      bool solveStep(int) override {
        newton.solve(mode, y, yp, s);
        return true;
      }
      numeric::TrialVerdict tryStep(double) override {
        newton.apply(y, yp, s);
        return numeric::TrialVerdict::Accept;
      }
      numeric::StepVerdict afterStep(double) override {
        noteFirst();
        best = std::min(best, s.residual);
        last = s;
        if (s.converged)
          return numeric::StepVerdict::Converged;
        if (!s.solvable && mode == Mode::Jumps)
          return numeric::StepVerdict::Stop; // try the nearest point
        return numeric::StepVerdict::Continue;
      }
      /// The jump space at the mode's first iterate.
      void noteFirst() {
        if (!first)
          return;
        out.jumpDim = s.jumpDim;
        out.index = s.index;
        out.written = s.written;
        first = false;
      }

      Newton &newton;
      Mode mode;
      VectorXd &y, &yp;
      InitOutcome &out;
      double &best;
      StepResult &last;
      StepResult s;
      bool first = true;
    } steps(newton, mode, y, yp, out, best, last);
    switch (numeric::iterateNewton(steps, {50}).end) {
    case numeric::NewtonEnd::EvaluationFailed:
      out.failure = domainFailure(steps.s.domainError);
      if (steps.s.domainRow >= 0) {
        out.domainRow = steps.s.domainRow;
        out.domainY.assign(y.data(), y.data() + n);
      }
      return out;
    case numeric::NewtonEnd::Converged:
      out.ok = true;
      out.nearestPoint = mode == Mode::Nearest;
      out.residual = steps.s.residual;
      out.y.assign(y.data(), y.data() + n);
      out.yp.assign(yp.data(), yp.data() + n);
      return out;
    default:
      break;
    }
    reached = y;
    if (mode == Mode::Jumps && log)
      *log << "warning: the start values cannot be made consistent along "
              "the jump directions; taking the consistent point nearest to "
              "them (nominal-scaled)\n";
  }
  out.residual = best;
  std::string rows;
  int levels = last.levels;
  for (size_t i = 0; i < last.badRows.size() && i < 5; ++i)
    rows += (i ? ", " : "") + newton.describe(last.badRows[i], levels);
  out.failure = noConsistentPoint(rows, best) +
                guessesOf(ev, set, c, last.badRows, y0, reached);
  return out;
}

constexpr int kMaxMovesListed = 20;
/// The dense re-initialization's size limit (as the simulator's for the
/// start): n x 2n least squares and Wong sequences at every iterate.
constexpr int kMaxDenseJumpUnknowns = 10000;

namespace {

/// A move is reported when the 10 digits it is printed with show it: a
/// Newton iteration's last step from a consistent start (2e-12 on z^2 =
/// 1 - y) was listed as "'z' from 1 to 1".
bool movedBeyondRoundOff(const ldae_model &m, int i, double before,
                         double after) {
  double nom = m.nominal ? m.nominal[i] : 1.0;
  return std::fabs(after - before) > 1e-10 * std::max(nom, std::fabs(before));
}

/// Logs the moves under `header`; returns how many unknowns moved.
int listMoves(const ModelEval &ev, const std::vector<double> &before,
              const double *after, std::ostream *log,
              const std::string &header) {
  const ldae_model &m = ev.model();
  int moved = 0;
  for (int i = 0; i < ev.n(); ++i) {
    if (!movedBeyondRoundOff(m, i, before[i], after[i]))
      continue;
    ++moved;
    if (!log)
      continue;
    if (moved == 1)
      *log << header << "\n";
    // A large model moves thousands of values; the first ones tell the
    // story, the count tells the rest.
    if (moved <= kMaxMovesListed)
      *log << fmt::format("  '{}' from {:.10g} to {:.10g} (by {:.3g})\n",
                          ev.varName(i), before[i], after[i],
                          after[i] - before[i]);
  }
  if (log && moved > kMaxMovesListed)
    *log << fmt::format("  ... and {} more\n", moved - kMaxMovesListed);
  return moved;
}

} // namespace

void reportMoves(const ModelEval &ev, const std::vector<double> &before,
                 const double *after, std::ostream *log) {
  if (log && listMoves(ev, before, after, log, "initialization moved:") == 0)
    *log << "initialization: the start values are consistent\n";
}

int countMoves(const ModelEval &ev, const std::vector<double> &before,
               const double *after) {
  return listMoves(ev, before, after, nullptr, "");
}

InitOutcome reinitializeAfterEvent(const ModelEval &ev, int set, double t,
                                   const std::vector<double> &y,
                                   const std::vector<double> &yp,
                                   const std::vector<int> &held,
                                   std::ostream *log) {
  InitConditions c = InitConditions::afterEvent(ev.model(), held);
  InitOutcome out;
  bool done = false;
  if (usesSparseInit(ev)) {
    out = initializeSparse(ev, set, t, y, yp, c);
    done = out.ok || out.applicable;
  }
  if (!done && ev.n() > kMaxDenseJumpUnknowns) {
    out.failure = fmt::format(
        "{}; and the re-initialization along the jump space is dense: {} "
        "unknowns are more than it handles ({})",
        out.failure, ev.n(), kMaxDenseJumpUnknowns);
    return out;
  }
  if (!done)
    out = initializeAlongJumps(ev, set, t, y, yp, c, log);
  if (!out.ok)
    return out;
  out.jumped = listMoves(ev, y, out.y.data(), log,
                         fmt::format("re-initialization at t = {:.10g} "
                                     "moved:",
                                     t));
  return out;
}

bool algebraicDerivatives(const ModelEval &ev, int set, double t,
                          const std::vector<double> &y,
                          std::vector<double> &yp) {
  const int *diff = ev.set(set).is_differential;
  const int n = ev.n();
  if (std::all_of(diff, diff + n, [](int d) { return d != 0; }))
    return false;
  const double dt = 1.4901161193847656e-08 * (1.0 + std::fabs(t));
  std::vector<double> ahead(n), aheadYp = yp;
  for (int i = 0; i < n; ++i)
    ahead[i] = y[i] + dt * yp[i];
  const int *d = diff;
  std::vector<int> held;
  for (int i = 0; i < n; ++i)
    if (d[i])
      held.push_back(i);
  InitOutcome c = reinitializeAfterEvent(ev, set, t + dt, ahead, aheadYp, held,
                                         nullptr);
  if (!c.ok || c.nearestPoint)
    return false;
  for (int i = 0; i < n; ++i)
    if (!diff[i] && std::isfinite(c.y[i]))
      yp[i] = (c.y[i] - y[i]) / dt;
  return true;
}

void settleAlgebraic(const ModelEval &ev, int set, double t,
                     std::vector<double> &y, std::vector<double> &yp) {
  const int *diff = ev.set(set).is_differential;
  std::vector<int> held;
  for (int i = 0; i < ev.n(); ++i)
    if (diff[i])
      held.push_back(i);
  if (held.size() == size_t(ev.n()))
    return;
  InitOutcome c = reinitializeAfterEvent(ev, set, t, y, yp, held, nullptr);
  if (c.ok && !c.nearestPoint) {
    y = c.y;
    yp = c.yp;
  }
}


} // namespace ldae::runtime
