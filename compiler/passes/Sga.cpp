// The SGA on a flat model (see Sga.h and docs/sga.md). Each step:
//
//  1. sample points (ManifoldSampler.h): an anchor on the constraints
//     found so far (the start values, the unknowns without one computed
//     from their equations, projected by Gauss–Newton; later the previous
//     anchor projected), moved along random tangent directions and in
//     time and projected back; random points near the start values as the
//     fallback;
//  2. the rows' A-parts (partial derivatives w.r.t. the columns) and
//     remainders (the rows at D = 0), symbolically and at every point;
//  3. the generic rank of A by SVD (the largest rank over the points), and
//     Gaussian elimination of that many pivots, chosen numerically (an
//     entry counts as nonzero when it is so at every point; among the
//     large ones the sparsest, and the model's own equations before
//     tangency rows), carried out on the symbolic rows and at every point;
//  4. the rows left over have an A-part that vanishes on the manifold:
//     their remainders are candidate constraints. One that vanishes at
//     the points already holds; the others are added together, or in
//     halves when that fails, down to one at a time, the points projected
//     again after each (a candidate that then holds depended on the ones
//     before it). A projection that finds no point means P_f is empty.
//
// Every step starts the elimination afresh from the equations and all
// tangency rows, so a pivot that vanishes on the new, smaller manifold is
// never kept.
#include "passes/Sga.h"
#include "passes/ManifoldSampler.h"
#include "passes/PassContext.h"

#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "ir/Substitute.h"

#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <set>

namespace ldae::passes {

namespace {

constexpr int kPoints = 3;         // sample points per step
constexpr double kRankTol = 1e-9;  // singular values below count as 0
constexpr double kZeroTol = 1e-8;  // equilibrated |a_ic| below: vanishes
constexpr double kHoldTol = 1e-8;  // |phi| / its scale below: holds
constexpr double kMinEvaluationBudget = 1e6; // small models: ample
constexpr double kPivotBand = 0.1; // pivots within this of the largest

using Point = SamplePoint;

/// Scales the columns of A to largest entry 1, then its rows (and r with
/// them) likewise, so that "vanishes" and ranks do not depend on units: a
/// picofarad capacitor beside a henry inductor is not a zero. Row
/// operations on the scaled rows are those on the rows, up to row scale.
void equilibrate(Eigen::MatrixXd &A, Eigen::VectorXd &r) {
  if (A.rows() == 0 || A.cols() == 0) // Eigen's maxCoeff of nothing crashes
    return;
  for (Eigen::Index c = 0; c < A.cols(); ++c) {
    double m = A.col(c).cwiseAbs().maxCoeff();
    if (m > 0 && std::isfinite(m))
      A.col(c) /= m;
  }
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    double m = A.cols() > 0 ? A.row(i).cwiseAbs().maxCoeff() : 0.0;
    if (m > 0 && std::isfinite(m)) {
      A.row(i) /= m;
      r[i] /= m;
    }
  }
}

std::vector<int> merged(const std::vector<int> &a, const std::vector<int> &b) {
  std::vector<int> out;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(),
                 std::back_inserter(out));
  return out;
}

/// One row during elimination: sparse symbolic A-part and remainder, and
/// their values at every point.
struct WorkRow {
  std::vector<ir::ExprRef> coef; // per column, nullptr: zero
  ir::ExprRef rem = nullptr;
  std::vector<int> sources;
  bool pivoted = false;
};

class Sga {
public:
  Sga(PassContext &ctx, const MatchingResult &mr, SgaResult &out)
      : m_(ctx.model), ex_(m_.ctx()), mr_(mr), out_(out), diff_(ex_) {}

  void run();

private:
  const ir::Model &m_;
  ir::ExprContext &ex_;
  const MatchingResult &mr_;
  SgaResult &out_;
  ir::Differentiator diff_;
  std::map<ir::VarKey, int> columns_; // top derivative -> column
  int column(ir::VarKey k) const {
    auto it = columns_.find(k);
    return it == columns_.end() ? -1 : it->second;
  }
  /// Sample points on the constraints found so far, whose equations are
  /// out_.constraints' expressions in the same order.
  std::unique_ptr<ManifoldSampler> sampler_;
  std::set<int> gaveConstraint_; // rows whose remainder became a constraint
  bool undecided_ = false;       // no point of the constraints could be found
  bool overBudget() const {
    return sampler_->evaluations() > sampler_->evaluationBudget;
  }
  std::string budgetReason() const {
    return fmt::format("its constraints grew too large to evaluate: "
                       "differentiating and projecting them reached their "
                       "budget of {:.2g} expression nodes ({} equations)",
                       sampler_->evaluationBudget, mr_.equations.size());
  }
  /// Remainders that held on the manifold when found: constraints the
  /// others imply (used to name a written-out hidden constraint redundant).
  std::vector<SgaConstraintExpr> implied_;
  void findImpliedEquations();

  void buildForm();
  /// Points on the constraints: perturbations of the anchor, else (with
  /// `draw`) random draws near the start values.
  bool samplePoints(std::vector<Point> &pts, bool draw = true) {
    return sampler_->samplePoints(pts, kPoints, draw);
  }
  /// Keeps the first `count` constraints.
  void truncateConstraints(size_t count) {
    out_.constraints.resize(count);
    sampler_->truncate(count);
  }
  bool holds(ir::ExprRef phi, const std::vector<Point> &pts, double scale);
  /// One step; false when P_f turned out empty.
  bool step(std::vector<Point> &pts, bool &grew);
  void addConstraint(ir::ExprRef phi, std::vector<int> sources);
  void finish(const std::vector<Point> &pts);
  /// Rank of the constraints' Jacobian (w.r.t. the slots) at p.
  int constraintRank(const Point &p);
  std::vector<WorkRow> evaluateRows(const std::vector<Point> &pts,
                                    std::vector<Eigen::MatrixXd> &A,
                                    std::vector<Eigen::VectorXd> &r);
  std::vector<std::pair<int, int>> eliminate(std::vector<WorkRow> &rows,
                                             std::vector<Eigen::MatrixXd> &A,
                                             std::vector<Eigen::VectorXd> &r,
                                             int rank);
};

void Sga::buildForm() {
  SgaForm &f = out_.form;
  const size_t nu = mr_.unknowns.size();
  f.top.assign(nu, 1);
  for (size_t j = 0; j < nu; ++j)
    f.top[j] = static_cast<unsigned>(std::max(1, mr_.originalOrder[j]));
  // An equation nonlinear in a top derivative makes that derivative a
  // slot (w = x'); repeat until every row is linear in its columns.
  for (int round = 0; round < 4; ++round) {
    bool changed = false;
    for (int e : mr_.equations) {
      ir::ExprRef res = m_.equations[e].residual;
      for (ir::VarKey k : ir::freeVariables(res)) {
        if (k.var >= mr_.unknownIndex.size() || mr_.unknownIndex[k.var] < 0)
          continue;
        int j = mr_.unknownIndex[k.var];
        if (k.order != f.top[j])
          continue;
        ir::ExprRef a = diff_.partial(res, k);
        for (ir::VarKey q : ir::freeVariables(a)) {
          if (q.var >= mr_.unknownIndex.size() || mr_.unknownIndex[q.var] < 0)
            continue;
          int jq = mr_.unknownIndex[q.var];
          if (q.order == f.top[jq]) {
            ++f.top[j];
            changed = true;
            break;
          }
        }
        if (changed)
          break;
      }
    }
    if (!changed)
      break;
  }
  for (size_t j = 0; j < nu; ++j) {
    ir::VarId v = mr_.unknowns[j];
    for (unsigned k = 0; k < f.top[j]; ++k)
      f.slots.push_back({v, k});
    f.columns.push_back({v, f.top[j]});
  }
}

bool Sga::holds(ir::ExprRef phi, const std::vector<Point> &pts, double scale) {
  for (const Point &p : pts) {
    bool ok = true;
    double v = valueAt(phi, sampler_->env(p), ok);
    if (!ok || std::abs(v) > kHoldTol * std::max(scale, 1e-12))
      return false;
  }
  return true;
}

void Sga::addConstraint(ir::ExprRef phi, std::vector<int> sources) {
  SgaConstraintExpr c;
  c.expr = phi;
  c.sources = std::move(sources);
  c.generation = out_.generations;
  sampler_->addEquation(phi, c.generation);
  SgaRow row;
  row.residual = diff_.timeDerivative(phi);
  row.sources = c.sources;
  row.constraint = static_cast<int>(out_.constraints.size());
  out_.constraints.push_back(std::move(c));
  out_.rows.push_back(std::move(row));
}

std::vector<WorkRow> Sga::evaluateRows(const std::vector<Point> &pts,
                                       std::vector<Eigen::MatrixXd> &A,
                                       std::vector<Eigen::VectorXd> &r) {
  const SgaForm &f = out_.form;
  const size_t nr = out_.rows.size(), nc = f.columns.size();
  ir::Substitution atZero(ex_);
  for (ir::VarKey k : f.columns)
    atZero.set(ex_.var(k), ex_.zero());
  std::vector<WorkRow> rows(nr);
  for (size_t i = 0; i < nr; ++i) {
    WorkRow &w = rows[i];
    ir::ExprRef res = out_.rows[i].residual;
    w.coef.assign(nc, nullptr);
    for (ir::VarKey k : ir::freeVariables(res)) {
      int c = column(k);
      if (c >= 0)
        w.coef[c] = diff_.partial(res, k);
    }
    w.rem = atZero.apply(res);
    w.sources = out_.rows[i].sources;
  }
  A.assign(pts.size(), Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nr),
                                             static_cast<Eigen::Index>(nc)));
  r.assign(pts.size(), Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nr)));
  for (size_t s = 0; s < pts.size(); ++s) {
    ir::EvalEnv env = sampler_->env(pts[s]);
    for (size_t i = 0; i < nr; ++i) {
      bool ok = true;
      for (size_t c = 0; c < nc; ++c)
        if (rows[i].coef[c])
          A[s](static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) =
              valueAt(rows[i].coef[c], env, ok);
      r[s][static_cast<Eigen::Index>(i)] = valueAt(rows[i].rem, env, ok);
    }
  }
  return rows;
}

std::vector<std::pair<int, int>> Sga::eliminate(std::vector<WorkRow> &rows,
                                                std::vector<Eigen::MatrixXd> &A,
                                                std::vector<Eigen::VectorXd> &r,
                                                int rank) {
  const int nr = static_cast<int>(rows.size());
  const int nc = static_cast<int>(out_.form.columns.size());
  const size_t np = A.size();
  std::vector<char> colDone(static_cast<size_t>(nc), 0);
  std::vector<std::pair<int, int>> pivots;
  auto ratio = [&](int i, int c) {
    double least = INFINITY;
    for (size_t s = 0; s < np; ++s)
      least = std::min(least, std::abs(A[s](i, c)));
    return least;
  };
  // The model's equations are pivots before tangency rows: then the
  // equations left over are the redundant ones, and the vector field on
  // P_f is made of the user's own equations where they suffice.
  for (int phase = 0; phase < 2 && static_cast<int>(pivots.size()) < rank;
       ++phase) {
    while (static_cast<int>(pivots.size()) < rank) {
      std::vector<int> rowNnz(static_cast<size_t>(nr), 0),
          colNnz(static_cast<size_t>(nc), 0);
      double best = 0;
      for (int i = 0; i < nr; ++i) {
        if (rows[i].pivoted || (phase == 0 && out_.rows[i].constraint >= 0))
          continue;
        for (int c = 0; c < nc; ++c) {
          if (colDone[c])
            continue;
          double q = ratio(i, c);
          if (q > kZeroTol) {
            ++rowNnz[i];
            ++colNnz[c];
            best = std::max(best, q);
          }
        }
      }
      if (best <= kZeroTol)
        break;
      int pr = -1, pcol = -1;
      long bestCost = 0;
      double bestQ = 0;
      for (int i = 0; i < nr; ++i) {
        if (rowNnz[i] == 0)
          continue;
        for (int c = 0; c < nc; ++c) {
          if (colDone[c])
            continue;
          double q = ratio(i, c);
          if (q < kPivotBand * best)
            continue;
          long cost = static_cast<long>(rowNnz[i] - 1) * (colNnz[c] - 1);
          if (pr < 0 || cost < bestCost || (cost == bestCost && q > bestQ)) {
            pr = i;
            pcol = c;
            bestCost = cost;
            bestQ = q;
          }
        }
      }
      rows[pr].pivoted = true;
      colDone[pcol] = 1;
      pivots.emplace_back(pr, pcol);
      ir::ExprRef piv = rows[pr].coef[pcol];
      std::vector<int> pattern;
      for (int c = 0; c < nc; ++c)
        if (c != pcol && rows[pr].coef[c])
          pattern.push_back(c);
      for (int j = 0; j < nr; ++j) {
        if (j == pr || rows[j].pivoted || !rows[j].coef[pcol])
          continue;
        bool vanishes = true;
        for (size_t s = 0; s < np; ++s)
          vanishes = vanishes && std::abs(A[s](j, pcol)) <= kZeroTol;
        if (vanishes) {
          // Vanishes on the manifold: nothing to eliminate there.
          rows[j].coef[pcol] = nullptr;
          for (size_t s = 0; s < np; ++s)
            A[s](j, pcol) = 0;
          continue;
        }
        ir::ExprRef mu = ex_.div(rows[j].coef[pcol], piv);
        for (int c = 0; c < nc; ++c) {
          if (c == pcol || !rows[pr].coef[c])
            continue;
          ir::ExprRef term = ex_.mul(mu, rows[pr].coef[c]);
          rows[j].coef[c] =
              rows[j].coef[c] ? ex_.sub(rows[j].coef[c], term) : ex_.neg(term);
        }
        rows[j].coef[pcol] = nullptr;
        rows[j].rem = ex_.sub(rows[j].rem, ex_.mul(mu, rows[pr].rem));
        rows[j].sources = merged(rows[j].sources, rows[pr].sources);
        // The pivot row's nonzeros are its symbolic pattern.
        for (size_t s = 0; s < np; ++s) {
          double m = A[s](j, pcol) / A[s](pr, pcol);
          for (int c : pattern)
            A[s](j, c) -= m * A[s](pr, c);
          A[s](j, pcol) = 0;
          r[s][j] -= m * r[s][pr];
        }
      }
    }
  }
  return pivots;
}

bool Sga::step(std::vector<Point> &pts, bool &grew) {
  grew = false;
  std::vector<Eigen::MatrixXd> A;
  std::vector<Eigen::VectorXd> r;
  std::vector<WorkRow> rows = evaluateRows(pts, A, r);
  const int nr = static_cast<int>(rows.size());
  int rank = 0;
  std::vector<std::vector<double>> scale(A.size(), std::vector<double>(nr));
  for (size_t s = 0; s < A.size(); ++s) {
    for (int i = 0; i < nr; ++i)
      scale[s][i] = std::abs(r[s][i]);
    equilibrate(A[s], r[s]); // entries now relative: 1 the largest
    if (A[s].size() > 0) {
      Eigen::BDCSVD<Eigen::MatrixXd> svd(A[s]);
      const Eigen::VectorXd &sv = svd.singularValues();
      int rk = 0;
      for (Eigen::Index i = 0; i < sv.size(); ++i)
        if (sv[i] > kRankTol * sv[0])
          ++rk;
      rank = std::max(rank, rk);
    }
  }
  std::vector<std::pair<int, int>> pivots = eliminate(rows, A, r, rank);
  out_.pivotRows.clear();
  for (auto [row, col] : pivots)
    out_.pivotRows.push_back(row);

  // Candidates: rows without a pivot whose A-part vanishes at every point.
  std::vector<int> candidates;
  for (int i = 0; i < nr; ++i) {
    if (rows[i].pivoted)
      continue;
    bool zero = true;
    for (size_t s = 0; s < A.size() && zero; ++s)
      zero = A[s].cols() == 0 || A[s].row(i).cwiseAbs().maxCoeff() <= kZeroTol;
    if (zero)
      candidates.push_back(i);
  }
  auto scaleOf = [&](int i) {
    double sc = 0;
    for (size_t s = 0; s < A.size(); ++s)
      sc = std::max(sc, scale[s][i]);
    return std::max(sc, 1.0);
  };
  auto skipped = [&](int i) {
    const SgaRow &own = out_.rows[i];
    return own.constraint < 0 &&
           std::find(out_.redundant.begin(), out_.redundant.end(),
                     own.sources.front()) != out_.redundant.end();
  };
  // All new candidates at once first: one projection instead of one per
  // constraint (a 50-body chain has 150 of them). Only when the points
  // cannot be found or the constraints turn out dependent is each added
  // alone, to name the conflict or the redundant equation.
  std::vector<int> fresh;
  for (int i : candidates)
    if (!skipped(i) && !holds(rows[i].rem, pts, scaleOf(i)))
      fresh.push_back(i);
  // A set that cannot be added whole (no point found, or dependent) is
  // halved, each half tried in order, down to single candidates, which
  // the loop below adds one at a time: a conflict or a redundant equation
  // among Andrews' 63 primary constraints costs a few halvings, not 63
  // projections. Halves are tried without random draws: a failed half
  // costs at most two projections of the failure budget.
  std::set<int> batched;
  // A half is tried only while every candidate before it has been added:
  // a conflict is then named where the equations, in the user's order,
  // first cannot hold together (x^2 = 1, then sin(x) = 0.5), not at an
  // earlier equation that a later batch happens to contradict.
  bool inOrder = true;
  std::function<void(size_t, size_t)> addChunk = [&](size_t lo, size_t hi) {
    if (!inOrder || overBudget())
      return;
    if (hi - lo < 2) {
      inOrder = hi == lo;
      return;
    }
    const size_t ncons = out_.constraints.size(), nrows = out_.rows.size();
    for (size_t k = lo; k < hi && !overBudget(); ++k)
      addConstraint(rows[fresh[k]].rem, rows[fresh[k]].sources);
    if (overBudget()) {
      truncateConstraints(ncons);
      out_.rows.resize(nrows);
      return;
    }
    std::vector<Point> trial;
    if (samplePoints(trial, /*draw=*/false) &&
        constraintRank(trial[0]) == static_cast<int>(out_.constraints.size())) {
      pts = std::move(trial);
      batched.insert(fresh.begin() + static_cast<long>(lo),
                     fresh.begin() + static_cast<long>(hi));
      gaveConstraint_.insert(fresh.begin() + static_cast<long>(lo),
                             fresh.begin() + static_cast<long>(hi));
      grew = true;
      return;
    }
    truncateConstraints(ncons);
    out_.rows.resize(nrows);
    const size_t mid = lo + (hi - lo) / 2;
    addChunk(lo, mid);
    addChunk(mid, hi);
  };
  addChunk(0, fresh.size());
  for (int i : candidates) {
    if (batched.count(i))
      continue;
    if (overBudget()) {
      undecided_ = true;
      return false;
    }
    const double sc = scaleOf(i);
    const SgaRow own = out_.rows[i]; // a copy: rows grow below
    if (skipped(i))
      continue;
    if (holds(rows[i].rem, pts, sc)) {
      if (!gaveConstraint_.count(i))
        implied_.push_back({rows[i].rem, rows[i].sources, 0});
      // A model equation whose row is implied by the others on the current
      // manifold is redundant, unless its row gave a constraint before.
      if (own.constraint < 0 && !gaveConstraint_.count(i) &&
          std::find(out_.redundant.begin(), out_.redundant.end(),
                    own.sources.front()) == out_.redundant.end())
        out_.redundant.push_back(own.sources.front());
      continue;
    }
    addConstraint(rows[i].rem, rows[i].sources);
    gaveConstraint_.insert(i);
    sampler_->stationaryFailure = false;
    if (!samplePoints(pts)) {
      if (!sampler_->stationaryFailure) {
        // No point found, but no proof of a conflict either.
        undecided_ = true;
        return false;
      }
      out_.conflict = static_cast<int>(out_.constraints.size()) - 1;
      return false;
    }
    // A model equation whose gradient depends on the constraints before
    // it on the manifold they define (a mechanism's redundant loop
    // closure: it at most picks a branch) is redundant, locally implied:
    // named, and left out of the constraints.
    if (own.constraint < 0 && rows[i].sources.size() == 1 &&
        constraintRank(pts[0]) < static_cast<int>(out_.constraints.size())) {
      out_.redundant.push_back(own.sources.front());
      truncateConstraints(out_.constraints.size() - 1);
      out_.rows.pop_back();
      if (!samplePoints(pts)) {
        // No point without it, yet no conflict named either (a fuzzer's
        // grounded pin written twice made NoSolution with no constraint
        // to name, and the report crashed on it).
        undecided_ = true;
        return false;
      }
      continue;
    }
    grew = true;
  }
  return true;
}

int Sga::constraintRank(const Point &p) {
  const size_t ns = out_.form.slots.size(), ncons = out_.constraints.size();
  if (ncons == 0 || ns == 0)
    return 0;
  Eigen::MatrixXd J;
  sampler_->jacobianAt(p, ncons, J);
  Eigen::VectorXd unused = Eigen::VectorXd::Zero(J.rows());
  equilibrate(J, unused);
  Eigen::BDCSVD<Eigen::MatrixXd> svd(J);
  const Eigen::VectorXd &sv = svd.singularValues();
  int rank = 0;
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv[i] > kRankTol * sv[0])
      ++rank;
  return rank;
}

// An equation written as a primary constraint may be what the other
// equations imply after differentiation (a pendulum's velocity constraint
// written out): then a remainder found later held because of it. It is
// redundant when the other constraints with that remainder in its place
// still imply it.
void Sga::findImpliedEquations() {
  const std::vector<SgaConstraintExpr> all = out_.constraints;
  const std::vector<SampledEquation> allEquations = sampler_->equations();
  // The anchor is on all of them.
  const ManifoldSampler::AnchorState anchor = sampler_->anchorState();
  for (size_t c = 0; c < all.size(); ++c) {
    if (all[c].generation != 0 || all[c].sources.size() != 1)
      continue;
    const int e = all[c].sources.front();
    for (const SgaConstraintExpr &phi : implied_) {
      if (std::binary_search(phi.sources.begin(), phi.sources.end(), e))
        continue;
      out_.constraints.clear();
      sampler_->equations().clear();
      for (size_t k = 0; k < all.size(); ++k)
        if (k != c) {
          out_.constraints.push_back(all[k]);
          sampler_->equations().push_back(allEquations[k]);
        }
      const size_t rowsBefore = out_.rows.size();
      // All but c: the anchor meets them.
      sampler_->anchorMeetsAll();
      addConstraint(phi.expr, phi.sources);
      out_.rows.resize(rowsBefore);
      std::vector<Point> pts;
      bool implied = samplePoints(pts) && holds(all[c].expr, pts, 1.0);
      out_.constraints = all;
      sampler_->equations() = allEquations;
      sampler_->setAnchorState(anchor);
      if (implied) {
        out_.implied.push_back(e);
        break;
      }
    }
  }
}

void Sga::finish(const std::vector<Point> &pts) {
  // Only an over-determined model can have one (a square one would then
  // be under-determined elsewhere).
  if (out_.redundant.empty() && mr_.equations.size() > mr_.unknowns.size())
    findImpliedEquations();
  const size_t ns = out_.form.slots.size(), nc = out_.form.columns.size();
  // Ranks are generic: the largest over the points (a point may sit near
  // a configuration where A loses rank). The kernel is taken there.
  size_t best = 0;
  int rank = -1, crank = 0;
  Eigen::MatrixXd kernel;
  for (size_t k = 0; k < pts.size(); ++k) {
    crank = std::max(crank, constraintRank(pts[k]));
    std::vector<Eigen::MatrixXd> A;
    std::vector<Eigen::VectorXd> r;
    std::vector<Point> one{pts[k]};
    evaluateRows(one, A, r);
    if (nc == 0 || A[0].rows() == 0) {
      // No equation: every derivative is free (Eigen's SVD of an empty
      // matrix crashes).
      if (rank < 0) {
        rank = 0;
        kernel = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(nc),
                                           static_cast<Eigen::Index>(nc));
      }
      continue;
    }
    // Column scaling keeps which columns the kernel touches.
    equilibrate(A[0], r[0]);
    Eigen::BDCSVD<Eigen::MatrixXd> svd(A[0], Eigen::ComputeFullV);
    const Eigen::VectorXd &sv = svd.singularValues();
    int rk = 0;
    for (Eigen::Index i = 0; i < sv.size(); ++i)
      if (sv[0] > 0 && sv[i] > kRankTol * sv[0])
        ++rk;
    if (rk > rank) {
      rank = rk;
      best = k;
      kernel = svd.matrixV().rightCols(static_cast<Eigen::Index>(nc) - rk);
    }
  }
  rank = std::max(rank, 0);
  const Point &p = pts[best];
  // dim P_f: slots minus the rank of the constraints' Jacobian.
  out_.dof = static_cast<int>(ns) - crank;
  for (size_t c = 0; c < nc; ++c)
    if (kernel.rows() > 0 && kernel.cols() > 0 &&
        kernel.row(static_cast<Eigen::Index>(c)).norm() > 1e-8)
      out_.freeColumns.push_back(static_cast<int>(c));
  out_.freeFunctions = static_cast<int>(nc) - rank;
  out_.outcome = out_.freeFunctions > 0 ? SgaReport::Outcome::NotUnique
                                        : SgaReport::Outcome::Unique;
  out_.point.assign(p.x.data(), p.x.data() + p.x.size());
}

void Sga::run() {
  out_.ran = true;
  buildForm();
  for (size_t j = 0; j < out_.form.columns.size(); ++j)
    columns_[out_.form.columns[j]] = static_cast<int>(j);
  sampler_ = std::make_unique<ManifoldSampler>(m_, diff_, out_.form.slots);
  {
    // Expression nodes its projections may evaluate: 1000 n^2 for n
    // equations, 24x what Andrews' squeezer needs (2.5e5 for 77) and 87x
    // the 50-link chain's (7.2e5 for 250). A model whose constraints grow
    // by differentiation beyond that (Andrews with one der(der(v[5])):
    // minutes, 0.7 s now) is left undecided, as one with no point found.
    const double n = double(mr_.equations.size());
    sampler_->evaluationBudget = std::max(kMinEvaluationBudget, 1000 * n * n);
  }
  // Every row can be evaluated at a sample point (columns at 0).
  sampler_->acceptable = [this](const Point &p) {
    ir::EvalEnv env = sampler_->env(p);
    bool ok = true;
    for (const SgaRow &row : out_.rows)
      valueAt(row.residual, env, ok);
    return ok;
  };
  for (int e : mr_.equations) {
    SgaRow row;
    row.residual = m_.equations[e].residual;
    row.sources = {e};
    out_.rows.push_back(row);
  }
  // The unknowns without a start value are computed from the equations
  // that read no column (algebraic in the SGA's form).
  std::vector<ir::ExprRef> defining;
  for (const SgaRow &row : out_.rows) {
    bool algebraic = true;
    for (ir::VarKey k : ir::freeVariables(row.residual))
      algebraic = algebraic && column(k) < 0;
    if (algebraic)
      defining.push_back(row.residual);
  }
  sampler_->findAssignments(defining);
  const Point given = sampler_->startPoint();
  out_.startGuess.assign(given.x.data(), given.x.data() + given.x.size());
  std::vector<Point> pts;
  if (!samplePoints(pts)) {
    out_.ran = false;
    out_.skipped = overBudget() ? budgetReason()
                                : "no point where every equation is defined "
                                  "was found";
    return;
  }
  const size_t maxSteps = out_.form.slots.size() + 2;
  for (size_t k = 0; k < maxSteps; ++k) {
    ++out_.steps;
    bool grew = false;
    if (!step(pts, grew)) {
      if (undecided_) {
        out_.ran = false;
        out_.skipped = overBudget()
                           ? budgetReason()
                           : "no point satisfying the constraints was found "
                             "from the start values (Gauss-Newton did not "
                             "converge)";
        return;
      }
      out_.outcome = SgaReport::Outcome::NoSolution;
      ++out_.generations;
      return;
    }
    if (!grew)
      break;
    ++out_.generations;
  }
  finish(pts);
}

} // namespace

MatchingResult sgaInput(const ir::Model &m) {
  MatchingResult in;
  in.unknownIndex.assign(m.variables.size(), -1);
  for (ir::VarId v = 0; v < m.variables.size(); ++v)
    if (!m.variables[v].isDiscrete) {
      in.unknownIndex[v] = static_cast<int>(in.unknowns.size());
      in.unknowns.push_back(v);
    }
  in.originalOrder.assign(in.unknowns.size(), 0);
  for (size_t e = 0; e < m.equations.size(); ++e) {
    in.equations.push_back(static_cast<int>(e));
    for (ir::VarKey k : ir::freeVariables(m.equations[e].residual))
      if (k.var < in.unknownIndex.size() && in.unknownIndex[k.var] >= 0) {
        int &o = in.originalOrder[static_cast<size_t>(in.unknownIndex[k.var])];
        o = std::max(o, static_cast<int>(k.order));
      }
  }
  return in;
}

void runSga(PassContext &ctx, SgaResult &out) {
  Sga(ctx, out.input, out).run();
}

} // namespace ldae::passes
