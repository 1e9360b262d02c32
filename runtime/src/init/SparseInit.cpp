// Sparse initialization of index-1 models with initial equations or fixed
// algebraic values (see SparseInit.h).
#include "init/SparseInit.h"
#include "init/JumpRule.h"

#include "graph/Matching.h"
#include "graph/Scc.h"
#include "numeric/NewtonKernel.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace ldae::runtime {

namespace {

constexpr double kTol = 1e-10; // as the dense and index-1 Newton iterations
constexpr int kMaxIterations = 50;
/// How many rows and unknowns a failure message lists.
constexpr int kListed = 6;

enum class RowKind { Residual, Initial, Fixed, Keep };

/// The square system's layout: columns v_0..v_{n-1}, then x for every
/// differential unknown; rows F, G, fixed, keep.
class InitLayout {
public:
  InitLayout(const ModelEval &ev, int set, const InitConditions &c)
      : ev_(ev), n_(ev.n()) {
    const ldae_model &m = ev.model();
    const int *diff = ev.set(set).is_differential;
    xCol_.assign(n_, -1);
    for (int j = 0; j < n_; ++j)
      if (diff[j]) {
        xCol_[j] = n_ + int(xVar_.size());
        xVar_.push_back(j);
      }
    for (int j = 0; j < n_; ++j)
      if (c.isHeld(j))
        fixedVar_.push_back(j);
    ni_ = c.numInitial(m);
  }

  int n() const { return n_; }
  int numCols() const { return n_ + int(xVar_.size()); }
  int firstInitial() const { return n_; }
  int numInitial() const { return ni_; }
  int firstFixed() const { return n_ + ni_; }
  int firstKeep() const { return firstFixed() + int(fixedVar_.size()); }
  /// The x column of unknown j, or -1 when j is algebraic.
  int xCol(int j) const { return xCol_[j]; }
  /// The model unknown of column c.
  int var(int c) const { return c < n_ ? c : xVar_[c - n_]; }
  bool isX(int c) const { return c >= n_; }
  const std::vector<int> &fixedVars() const { return fixedVar_; }
  /// The column a fixed unknown's row holds.
  int fixedCol(int j) const { return xCol_[j] >= 0 ? xCol_[j] : j; }

  RowKind kind(int row) const {
    return row < n_                ? RowKind::Residual
           : row < firstFixed()    ? RowKind::Initial
           : row < firstKeep()     ? RowKind::Fixed
                                   : RowKind::Keep;
  }

  /// "der(x)" for a derivative column, "x" otherwise.
  std::string colName(int c, const int *diff) const {
    int j = var(c);
    return !isX(c) && diff[j] ? fmt::format("der({})", ev_.varName(j))
                              : ev_.varName(j);
  }

private:
  const ModelEval &ev_;
  int n_, ni_ = 0;
  std::vector<int> xCol_, xVar_, fixedVar_;
};

/// Builds a CSC matrix from entries given twice in the same order: once
/// to count them per column, once to place them (no per-column lists: a
/// model of 10^5 unknowns would allocate 2·10^5 small vectors per
/// iteration).
class CscBuilder {
public:
  explicit CscBuilder(int n) { a_.n = n, a_.colptr.assign(n + 1, 0); }
  void count(int col) { ++a_.colptr[col + 1]; }
  /// Call after counting, before the first place().
  void allocate() {
    for (int c = 0; c < a_.n; ++c)
      a_.colptr[c + 1] += a_.colptr[c];
    a_.rowind.resize(a_.colptr[a_.n]);
    a_.values.resize(a_.colptr[a_.n]);
    next_.assign(a_.colptr.begin(), a_.colptr.end() - 1);
  }
  void place(int row, int col, double v) {
    int q = next_[col]++;
    a_.rowind[q] = row;
    a_.values[q] = v;
  }
  CscMatrix take() { return std::move(a_); }

private:
  CscMatrix a_;
  std::vector<int> next_;
};

class SparseInit {
public:
  SparseInit(const ModelEval &ev, int set, double t,
             const std::vector<double> &y0, const std::vector<double> &yp0,
             const InitConditions &c)
      : ev_(ev), m_(ev.model()), set_(set), t_(t), L_(ev, set, c), y0_(y0),
        yp0_(yp0), diff_(ev.set(set).is_differential) {
    D_.assign(ev.n(), 1.0);
    if (m_.nominal)
      for (int j = 0; j < ev.n(); ++j)
        D_[j] = m_.nominal[j];
  }

  InitOutcome run() {
    InitOutcome out;
    y_ = y0_;
    yp_ = yp0_;
    if (L_.numInitial() > 0 && !ev_.hasInitJacobianCsc())
      return notApplicable("the model gives no sparse Jacobian of its "
                           "initial equations");
    if (!jumpRuleKeepsStates(ev_, set_, t_, y0_.data(), yp0_.data()))
      return notApplicable("the jump directions of the model as written "
                           "move differential values");
    if (!evaluate(out))
      return out;
    if (!structure(out))
      return out;
    // The Newton iteration on M (dy, dy') = -F: the residual judged before
    // the step, converged when it and the step are below kTol.
    struct Steps : numeric::NewtonSystem {
      Steps(SparseInit &s, InitOutcome &out) : s(s), out(out) {}
      bool evaluate(int iter) override {
        if (iter > 0 && !s.evaluate(out))
          return false;
        s.assemble();
        res = s.scaledResidual();
        best = std::min(best, res);
        return true;
      }
      bool solveStep(int iter) override {
        SparseLu lu;
        if (!lu.factor(s.A_)) {
          int c = lu.singularColumn();
          out.failure = fmt::format(
              "the initialization system is singular {}{}",
              iter == 0 ? "at the start values" : "at the current iterate",
              c >= 0 ? fmt::format(" (at '{}')", s.L_.colName(c, s.diff_))
                     : "");
          out.residual = best;
          // Singular from the start: the structure was right but the
          // numbers are not; the dense path (nearest point) may still find
          // a point.
          out.applicable = iter > 0;
          return false;
        }
        dz = s.b_;
        if (!lu.solve(dz.data()) || !s.project(dz)) {
          out.failure = "the initialization's linear solve failed";
          out.residual = best;
          return false;
        }
        return true;
      }
      numeric::TrialVerdict tryStep(double) override {
        step = 0;
        for (int c = 0; c < s.L_.numCols(); ++c) {
          int j = s.L_.var(c);
          double d = s.D_[j] * dz[c];
          if (s.L_.isX(c) || !s.diff_[j]) {
            s.y_[j] += d;
            step = std::max(step, std::fabs(dz[c]));
          } else {
            s.yp_[j] += d;
          }
        }
        return numeric::TrialVerdict::Accept;
      }
      numeric::StepVerdict afterStep(double) override {
        return res <= kTol && step <= kTol ? numeric::StepVerdict::Converged
                                           : numeric::StepVerdict::Continue;
      }

      SparseInit &s;
      InitOutcome &out;
      std::vector<double> dz;
      double res = 0, step = 0, best = INFINITY;
    } steps(*this, out);
    switch (numeric::iterateNewton(steps, {kMaxIterations}).end) {
    case numeric::NewtonEnd::Converged:
      out.ok = true;
      out.residual = steps.res;
      out.y = y_;
      out.yp = yp_;
      return out;
    case numeric::NewtonEnd::IterationLimit:
      out.residual = steps.best;
      out.failure = describeFailure(steps.best);
      return out;
    default: // the failure is in `out`
      return out;
    }
  }

private:
  InitOutcome notApplicable(std::string why) {
    InitOutcome out;
    out.applicable = false;
    out.failure = std::move(why);
    return out;
  }

  /// F, G and their Jacobians at the current iterate; false with the
  /// domain error in `out`.
  bool evaluate(InitOutcome &out) {
    int n = ev_.n(), ni = L_.numInitial();
    r_.assign(n, 0.0);
    g_.assign(ni, 0.0);
    int rc = ev_.residual(set_, t_, y_.data(), yp_.data(), r_.data());
    if (rc == 0)
      rc = ev_.jacobianPartsCsc(set_, t_, y_.data(), yp_.data(), Fy_, E_);
    if (rc) {
      out.failure = fmt::format("{} is outside its domain at the start values",
                                rc > 0 ? ev_.describeRow(rc - 1)
                                       : std::string("the residual"));
      if (rc > 0) {
        out.domainRow = rc - 1;
        out.domainY = y_;
      }
      return false;
    }
    // Hand-written models without initial equations may leave the init
    // functions NULL.
    rc = ni > 0 ? ev_.initResidual(t_, y_.data(), yp_.data(), g_.data()) : 0;
    if (rc == 0 && ni > 0)
      rc = ev_.initJacobianCsc(t_, y_.data(), yp_.data(), gy_, gyp_);
    if (rc) {
      out.failure = fmt::format(
          "{} is outside its domain at the start values",
          rc > 0 ? fmt::format("initial equation {}", rc) : "an initial "
                                                            "equation");
      return false;
    }
    return true;
  }

  /// Calls f(row, col, value, edge) for every entry of the F and G rows
  /// (nominal-scaled); `edge`: the entry belongs to the structure.
  template <typename F> void forEachEntry(F f) const {
    int n = ev_.n();
    for (int j = 0; j < n; ++j) {
      int x = L_.xCol(j);
      // dRow/dy and dRow/dy' of unknown j: an algebraic j has its y in the
      // v column; a differential j its y' there and its y in the x column.
      auto entry = [&](int r, double dy, double dyp) {
        dy *= D_[j];
        dyp *= D_[j];
        if (x < 0) {
          f(r, j, dy, true);
          return;
        }
        // A structural entry that vanishes at this point keeps both
        // edges: the matching must not depend on a coincidence.
        bool both = dy == 0 && dyp == 0;
        f(r, j, dyp, both || dyp != 0);
        f(r, x, dy, both || dy != 0);
      };
      for (int q = Fy_.colptr[j]; q < Fy_.colptr[j + 1]; ++q)
        entry(Fy_.rowind[q], Fy_.values[q], E_.values[q]);
      if (L_.numInitial() > 0)
        for (int q = m_.init_jac_colptr[j]; q < m_.init_jac_colptr[j + 1];
             ++q)
          entry(L_.firstInitial() + m_.init_jac_rowind[q], gy_[q], gyp_[q]);
    }
  }

  /// Index 1 in this form, the matching, the keep rows and the
  /// minimum-norm blocks; false (not applicable) when the form does not fit.
  bool structure(InitOutcome &out) {
    int n = ev_.n();
    double scale = std::max({1e-300, E_.maxAbs(), Fy_.maxAbs()});
    for (int j = 0; j < n; ++j)
      if (!diff_[j])
        for (int q = E_.colptr[j]; q < E_.colptr[j + 1]; ++q)
          if (std::fabs(E_.values[q]) > 1e-14 * scale) {
            out = notApplicable(fmt::format(
                "'{}' is algebraic but its derivative appears ({}): not "
                "index 1 in this form",
                ev_.varName(j), ev_.describeRow(E_.rowind[q])));
            return false;
          }
    int cols = L_.numCols();
    graph::BipartiteGraph g(L_.firstKeep(), cols);
    forEachEntry([&](int r, int c, double, bool edge) {
      if (edge)
        g.addEdge(r, c);
    });
    for (size_t k = 0; k < L_.fixedVars().size(); ++k)
      g.addEdge(L_.firstFixed() + int(k), L_.fixedCol(L_.fixedVars()[k]));
    // Derivatives and algebraic values first, then as few differential
    // values as the rows need.
    std::vector<char> vOnly(cols, 0);
    std::fill(vOnly.begin(), vOnly.begin() + n, 1);
    graph::Matching first = graph::maximumMatching(g, vOnly);
    match_ = graph::maximumMatching(g, {}, &first);
    std::vector<std::string> unmatched;
    for (int r = 0; r < g.numRows(); ++r)
      if (match_.rowMate[r] < 0 && int(unmatched.size()) < kListed)
        unmatched.push_back(describeRow(r));
    if (match_.size < g.numRows()) {
      out = notApplicable(fmt::format(
          "the conditions over-determine the start values structurally: "
          "{}",
          fmt::join(unmatched, ", ")));
      return false;
    }
    for (int c = 0; c < n; ++c)
      if (match_.colMate[c] < 0) {
        out = notApplicable(fmt::format(
            "'{}' is not determined by the equations at the start",
            L_.colName(c, diff_)));
        return false;
      }
    for (int c = n; c < cols; ++c) {
      if (match_.colMate[c] >= 0) {
        if (L_.kind(match_.colMate[c]) != RowKind::Fixed)
          ++out.moved;
        continue;
      }
      int row = g.addRow({c});
      match_.rowMate.push_back(-1);
      match_.match(row, c);
      keepCol_.push_back(c);
    }
    out.kept = int(keepCol_.size());
    graph_ = std::move(g);
    findProjectedBlocks();
    out.projected = int(freeKeep_.size());
    out.jumpDim = out.moved + n - int(std::count(diff_, diff_ + n, 1));
    out.index = 1;
    return true;
  }

  /// The moved differential values that an alternating path joins to a
  /// kept one, and those kept ones: searched backwards from every moved x
  /// (column -> the row matched to it -> that row's other columns).
  void findProjectedBlocks() {
    int n = ev_.n(), cols = L_.numCols();
    std::vector<std::vector<int>> colRows = graph_.columns();
    std::vector<char> isKeep(cols, 0);
    for (int c : keepCol_)
      isKeep[c] = 1;
    // The columns reachable from `starts`, each column's successors given
    // by `next(c, visit)`.
    std::vector<char> seen(cols, 0);
    auto reach = [&](const std::vector<int> &starts, auto next) {
      std::fill(seen.begin(), seen.end(), 0);
      std::vector<int> stack;
      auto visit = [&](int c) {
        if (!seen[c]) {
          seen[c] = 1;
          stack.push_back(c);
        }
      };
      for (int c : starts)
        visit(c);
      while (!stack.empty()) {
        int c = stack.back();
        stack.pop_back();
        next(c, visit);
      }
    };
    // Forward from the kept x columns: c -> rows containing c -> their
    // matched columns; the moved x columns reached are ambiguous.
    reach(keepCol_, [&](int c, auto &visit) {
      for (int r : colRows[c])
        if (L_.kind(r) != RowKind::Keep && match_.rowMate[r] >= 0)
          visit(match_.rowMate[r]);
    });
    std::vector<int> movedReached;
    for (int c = n; c < cols; ++c)
      if (seen[c] && !isKeep[c])
        movedReached.push_back(c);
    if (movedReached.empty())
      return;
    // Backwards from those: the kept columns whose value reaches them.
    reach(movedReached, [&](int c, auto &visit) {
      int r = match_.colMate[c];
      if (r >= 0 && L_.kind(r) != RowKind::Keep)
        for (int c2 : graph_.rows[r])
          visit(c2);
    });
    for (size_t k = 0; k < keepCol_.size(); ++k)
      if (seen[keepCol_[k]])
        freeKeep_.push_back(int(k));
    blockCols_ = movedReached;
    for (int k : freeKeep_)
      blockCols_.push_back(keepCol_[k]);
    std::sort(blockCols_.begin(), blockCols_.end());
  }

  /// A_ (nominal-scaled) and b_ = -(scaled residuals) at the iterate;
  /// rowScale_ for the convergence test.
  void assemble() {
    int cols = L_.numCols();
    CscBuilder builder(cols);
    // The F and G entries, then one 1 per fixed and per keep row.
    auto entries = [&](auto add) {
      forEachEntry([&](int r, int c, double v, bool edge) {
        if (edge)
          add(r, c, v);
      });
      int row = L_.firstFixed();
      for (int j : L_.fixedVars())
        add(row++, L_.fixedCol(j), 1.0);
      for (int c : keepCol_)
        add(row++, c, 1.0);
    };
    entries([&](int, int c, double) { builder.count(c); });
    builder.allocate();
    entries([&](int r, int c, double v) { builder.place(r, c, v); });
    A_ = builder.take();
    b_.assign(cols, 0.0);
    for (int i = 0; i < ev_.n(); ++i)
      b_[i] = -r_[i];
    for (int i = 0; i < L_.numInitial(); ++i)
      b_[L_.firstInitial() + i] = -g_[i];
    int row = L_.firstFixed();
    for (int j : L_.fixedVars())
      b_[row++] = -(y_[j] - y0_[j]) / D_[j];
    for (int c : keepCol_)
      b_[row++] = -(y_[L_.var(c)] - y0_[L_.var(c)]) / D_[L_.var(c)];
    rowScale_.assign(cols, 0.0);
    for (int q = 0; q < A_.nnz(); ++q)
      rowScale_[A_.rowind[q]] =
          std::max(rowScale_[A_.rowind[q]], std::fabs(A_.values[q]));
    double floor = 1e-8 * std::max(1.0, A_.maxAbs());
    for (double &s : rowScale_)
      s = std::max(s, floor);
  }

  /// max over the F, G and fixed rows of |residual| / row scale; the rows
  /// above kTol are remembered for the failure message.
  double scaledResidual() {
    double worst = 0;
    badRows_.clear();
    for (int i = 0; i < L_.firstKeep(); ++i) {
      double v = std::fabs(b_[i]) / rowScale_[i];
      worst = std::max(worst, v);
      if (v > kTol)
        badRows_.push_back(i);
    }
    return worst;
  }

  /// For the minimum-norm blocks: the step dz that meets every row but the
  /// free keep rows (A' dz = b') and minimizes the nominal-scaled distance
  /// of the block's differential values from their start values,
  /// 1/2 |d + dz_B|^2, from the sparse KKT system
  ///   [H  A'^T] [dz]   [-H d]
  ///   [A'  0  ] [l ] = [ b' ]      (H = 1 on the block's columns, else 0),
  /// factored by KLU: linear in the model's size however many blocks.
  bool project(std::vector<double> &dz) {
    if (freeKeep_.empty())
      return true;
    int cols = L_.numCols();
    std::vector<int> lambda(cols, 0); // row of A -> multiplier index or -1
    for (int k : freeKeep_)
      lambda[L_.firstKeep() + k] = -1;
    int m = 0;
    for (int &l : lambda)
      l = l < 0 ? -1 : m++;
    std::vector<char> inBlock(cols, 0);
    for (int c : blockCols_)
      inBlock[c] = 1;
    CscBuilder builder(cols + m);
    auto entries = [&](auto add) {
      for (int c = 0; c < cols; ++c) {
        if (inBlock[c])
          add(c, c, 1.0);
        for (int q = A_.colptr[c]; q < A_.colptr[c + 1]; ++q)
          if (int l = lambda[A_.rowind[q]]; l >= 0)
            add(cols + l, c, A_.values[q]);
      }
      for (int c = 0; c < cols; ++c)
        for (int q = A_.colptr[c]; q < A_.colptr[c + 1]; ++q)
          if (int l = lambda[A_.rowind[q]]; l >= 0)
            add(c, cols + l, A_.values[q]);
    };
    entries([&](int, int c, double) { builder.count(c); });
    builder.allocate();
    entries([&](int r, int c, double v) { builder.place(r, c, v); });
    CscMatrix kkt = builder.take();
    std::vector<double> rhs(cols + m, 0.0);
    for (int c : blockCols_) {
      int j = L_.var(c);
      rhs[c] = -(y_[j] - y0_[j]) / D_[j];
    }
    for (int r = 0; r < cols; ++r)
      if (lambda[r] >= 0)
        rhs[cols + lambda[r]] = b_[r];
    SparseLu lu;
    if (!lu.factor(kkt) || !lu.solve(rhs.data()))
      return false;
    std::copy(rhs.begin(), rhs.begin() + cols, dz.begin());
    return std::all_of(dz.begin(), dz.end(),
                       [](double v) { return std::isfinite(v); });
  }

  std::string describeRow(int row) const {
    switch (L_.kind(row)) {
    case RowKind::Residual:
      return ev_.describeRow(row);
    case RowKind::Initial:
      return fmt::format("initial equation {}", row - L_.firstInitial() + 1);
    case RowKind::Fixed:
      return fmt::format("the fixed value of '{}'",
                         ev_.varName(L_.fixedVars()[row - L_.firstFixed()]));
    case RowKind::Keep:
      break;
    }
    return fmt::format("the start value of '{}'",
                       ev_.varName(L_.var(keepCol_[row - L_.firstKeep()])));
  }

  /// Names the first block (in solve order) that holds a row not met: its
  /// equations, its iteration variables with their start values and
  /// reached values, and what to give.
  std::string describeFailure(double best) const {
    std::vector<char> bad(graph_.numRows(), 0);
    for (int r : badRows_)
      bad[r] = 1;
    std::vector<std::vector<int>> blocks = graph::bltBlocks(graph_, match_);
    const std::vector<int> *blk = nullptr;
    for (const auto &b : blocks)
      if (std::any_of(b.begin(), b.end(), [&](int r) { return bad[r]; })) {
        blk = &b;
        break;
      }
    if (!blk)
      return fmt::format("no consistent initial point (smallest residual "
                         "reached {:.3g})",
                         best);
    std::vector<std::string> rows, vars, names;
    for (size_t i = 0; i < blk->size() && int(i) < kListed; ++i) {
      int r = (*blk)[i];
      int c = match_.rowMate[r];
      int j = L_.var(c);
      bool der = !L_.isX(c) && diff_[j];
      rows.push_back(describeRow(r));
      vars.push_back(fmt::format("'{}' (guess {:.6g}, reached {:.6g})",
                                 L_.colName(c, diff_),
                                 der ? yp0_[j] : y0_[j],
                                 der ? yp_[j] : y_[j]));
      names.push_back(fmt::format("'{}'", L_.colName(c, diff_)));
    }
    std::string more =
        blk->size() > size_t(kListed)
            ? fmt::format(" and {} more", blk->size() - kListed)
            : std::string();
    return fmt::format(
        "no consistent initial point: a block of {} equation{} was not "
        "solved: {}{}; iteration variables {}{}; smallest residual reached "
        "{:.3g}; give start values near the solution for {}, or check the "
        "fixed values and initial equations",
        blk->size(), blk->size() == 1 ? "" : "s", fmt::join(rows, "; "), more,
        fmt::join(vars, ", "), more, best, fmt::join(names, ", "));
  }

  const ModelEval &ev_;
  const ldae_model &m_;
  int set_;
  double t_;
  InitLayout L_;
  const std::vector<double> &y0_, &yp0_;
  const int *diff_;
  std::vector<double> D_, y_, yp_, r_, g_, gy_, gyp_, b_, rowScale_;
  CscMatrix Fy_, E_, A_;
  graph::BipartiteGraph graph_;
  graph::Matching match_;
  std::vector<int> keepCol_, freeKeep_, blockCols_, badRows_;
};

} // namespace

InitOutcome initializeSparse(const ModelEval &ev, int set, double t,
                             const std::vector<double> &y0,
                             const std::vector<double> &yp0) {
  return initializeSparse(ev, set, t, y0, yp0,
                          InitConditions::atStart(ev.model()));
}

InitOutcome initializeSparse(const ModelEval &ev, int set, double t,
                             const std::vector<double> &y0,
                             const std::vector<double> &yp0,
                             const InitConditions &c) {
  return SparseInit(ev, set, t, y0, yp0, c).run();
}

} // namespace ldae::runtime
