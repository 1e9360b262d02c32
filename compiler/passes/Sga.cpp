// The SGA on a flat model (see Sga.h and docs/sga.md). Each step:
//
//  1. sample points: an anchor on the constraints found so far (the start
//     values, the unknowns without one computed from their equations,
//     projected by Gauss–Newton; later the previous anchor projected),
//     moved along random tangent directions and in time and projected
//     back; random points near the start values as the fallback;
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
#include "passes/PassContext.h"

#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "ir/Substitute.h"
#include "numeric/Newton.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>

namespace ldae::passes {

namespace {

constexpr int kPoints = 3;       // sample points per step
constexpr int kDrawAttempts = 5; // random draws per point (the fallback)
/// Sample points are the anchor (a point of the manifold reached from the
/// start values) displaced by this fraction of each slot's scale and
/// projected back: large enough that ranks there are generic, small
/// enough that Gauss–Newton comes back. Quartered after a failure.
constexpr double kPerturbSpread = 0.2;
constexpr int kPerturbAttempts = 3;
/// A tangent move is halved (up to kTangentHalvings times) until the
/// constraints are off by at most kTangentOff of their units there.
constexpr double kTangentOff = 0.05;
constexpr int kTangentHalvings = 16;
/// Steps from the anchor's time to a sample point's when the constraints
/// depend on time (a continuation: each projection starts close).
constexpr int kTimeSteps = 4;
/// Projections that may fail in one run before the SGA gives up as
/// undecided: each costs at most NewtonOptions::maxIterations steps, so
/// giving up costs a bounded multiple of one step's work, not seconds of
/// random draws (Andrews' squeezer spent up to 2.5 s so before it had
/// anchors).
constexpr int kFailureBudget = 24;
constexpr double kRankTol = 1e-9;  // singular values below count as 0
constexpr double kZeroTol = 1e-8;  // equilibrated |a_ic| below: vanishes
constexpr double kHoldTol = 1e-8;  // |phi| / its scale below: holds
constexpr double kPivotBand = 0.1; // pivots within this of the largest

struct Point {
  double t = 0;
  Eigen::VectorXd x; // slots
};

/// Where each Variable node of the SGA form lives.
class Layout {
public:
  Layout(const ir::Model &m, const SgaForm &f) : model_(m) {
    for (size_t i = 0; i < f.slots.size(); ++i)
      slot_[f.slots[i]] = static_cast<int>(i);
    for (size_t j = 0; j < f.columns.size(); ++j)
      column_[f.columns[j]] = static_cast<int>(j);
    params_ = m.parameterValues();
  }
  int slot(ir::VarKey k) const {
    auto it = slot_.find(k);
    return it == slot_.end() ? -1 : it->second;
  }
  int column(ir::VarKey k) const {
    auto it = column_.find(k);
    return it == column_.end() ? -1 : it->second;
  }
  /// The environment of point p with every column at 0.
  ir::EvalEnv env(const Point &p) const {
    ir::EvalEnv e;
    e.time = p.t;
    e.variable = [this, &p](ir::VarKey k) {
      int s = slot(k);
      if (s >= 0)
        return p.x[s];
      // Columns are 0 (remainders); discrete variables keep their start.
      if (k.order == 0 && k.var < model_.variables.size())
        return model_.variables[k.var].start;
      return 0.0;
    };
    e.parameter = [this](ir::ParamId q) {
      return q < params_.size() ? params_[q] : 0.0;
    };
    return e;
  }

private:
  const ir::Model &model_;
  std::map<ir::VarKey, int> slot_, column_;
  std::vector<double> params_;
};

double valueAt(ir::ExprRef e, const ir::EvalEnv &env, bool &ok) {
  auto v = ir::evaluate(e, env);
  if (!v || !std::isfinite(*v)) {
    ok = false;
    return 0;
  }
  return *v;
}

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
      : m_(ctx.model), ex_(m_.ctx()), mr_(mr), out_(out), diff_(ex_),
        rng_(20261124), t0_(m_.experiment.startTime.value_or(0.0)) {}

  void run();

private:
  const ir::Model &m_;
  ir::ExprContext &ex_;
  const MatchingResult &mr_;
  SgaResult &out_;
  ir::Differentiator diff_;
  std::mt19937 rng_;
  double t0_;
  std::unique_ptr<Layout> layout_;
  /// A point of the constraints found so far (of fewer of them, between
  /// a constraint's addition and the next projection): the sample points
  /// are its perturbations.
  std::optional<Point> anchor_;
  size_t anchorHolds_ = 0; // it meets constraints [0, anchorHolds_)
  /// The anchor is a random draw: the start values are tried first.
  bool anchorDrawn_ = false;
  int failures_ = 0; // failed projections (kFailureBudget)
  /// An equation of the model that computes an unknown without a start
  /// value (linear in it, with a coefficient that reads no slot).
  struct Assignment {
    ir::ExprRef residual;
    int slot;
    double coefficient;
  };
  std::vector<Assignment> assignments_;
  std::vector<char> assigned_; // per slot: computed by an assignment
  void findAssignments();
  void assignUnstarted(Point &p);
  /// The start values at the start time, those left out computed by the
  /// assignments.
  Point startPoint();
  /// Per constraint: the slots it reads and its partial derivatives.
  std::vector<std::vector<std::pair<int, ir::ExprRef>>> gradients_;
  std::set<int> gaveConstraint_; // rows whose remainder became a constraint
  /// A projection ended at a least-squares minimum off the constraints.
  bool stationaryFailure_ = false;
  bool undecided_ = false; // no point of the constraints could be found
  /// Remainders that held on the manifold when found: constraints the
  /// others imply (used to name a written-out hidden constraint redundant).
  std::vector<SgaConstraintExpr> implied_;
  void findImpliedEquations();

  void buildForm();
  /// Points on the constraints: perturbations of the anchor, else (with
  /// `draw`) random draws near the start values.
  bool samplePoints(std::vector<Point> &pts, bool draw = true);
  bool findAnchor();
  bool perturbAnchor(Point &p, int index);
  bool drawPoint(Point &p, int index);
  bool definedAt(const Point &p);
  /// The first `count` constraints' Jacobian w.r.t. the slots at p.
  bool jacobianAt(const Point &p, size_t count, Eigen::MatrixXd &J);
  /// Slot scales D, constraint weights and the scaled Jacobian
  /// W^-1 J D at p (empty when J cannot be evaluated there).
  void scaling(const Point &p, size_t count, Eigen::VectorXd &D,
               Eigen::VectorXd &weight, Eigen::MatrixXd &J);
  /// Onto the first `count` constraints; slots marked in `frozen` stay.
  bool project(Point &p, size_t count,
               const std::vector<char> *frozen = nullptr);
  /// Onto the first `count` constraints a generation at a time, each
  /// moving only the slots the generations before do not read; a plain
  /// projection where that fails.
  bool projectByGeneration(Point &p, size_t count);
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

bool Sga::project(Point &p, size_t count, const std::vector<char> *frozen) {
  if (count == 0)
    return true;
  if (failures_ >= kFailureBudget)
    return false;
  ir::EvalEnv env = layout_->env(p);
  Eigen::VectorXd D, weight;
  Eigen::MatrixXd J0;
  scaling(p, count, D, weight, J0);
  numeric::ResidualFn res = [&](const Eigen::VectorXd &y, Eigen::VectorXd &r) {
    p.x = D.cwiseProduct(y);
    r.resize(static_cast<Eigen::Index>(count));
    bool ok = true;
    for (size_t c = 0; c < count; ++c)
      r[static_cast<Eigen::Index>(c)] =
          valueAt(out_.constraints[c].expr, env, ok);
    r = r.cwiseQuotient(weight);
    return ok;
  };
  numeric::JacobianFn jac = [&](const Eigen::VectorXd &y, Eigen::MatrixXd &J) {
    p.x = D.cwiseProduct(y);
    bool ok = jacobianAt(p, count, J);
    J = weight.cwiseInverse().asDiagonal() * J * D.asDiagonal();
    // A zero column: the minimum-norm steps leave the slot where it is.
    for (size_t s = 0; frozen && s < frozen->size(); ++s)
      if ((*frozen)[s])
        J.col(static_cast<Eigen::Index>(s)).setZero();
    return ok;
  };
  numeric::NewtonOptions opts;
  // Round-off in constraints with large terms (a mechanism's forces) keeps
  // residuals well above 1e-13 of the coordinates.
  opts.tolerance = 1e-10;
  opts.maxIterations = 40;
  opts.backtrack = true;
  Eigen::VectorXd x = p.x.cwiseQuotient(D);
  numeric::NewtonResult nr = numeric::gaussNewton(res, jac, x, opts);
  p.x = D.cwiseProduct(x);
  if (nr.converged()) {
    // The test above is relative to the largest coordinate (a spring
    // force of 2000 N beside angles), looser than holds() judges each
    // constraint: two more steps, quadratically convergent, close the gap.
    numeric::NewtonOptions polish = opts;
    polish.tolerance = 0;
    polish.maxIterations = 2;
    Eigen::VectorXd converged = x;
    if (numeric::gaussNewton(res, jac, x, polish).status ==
        numeric::NewtonStatus::EvaluationFailed)
      x = converged;
    p.x = D.cwiseProduct(x);
    return true;
  }
  // A projection with frozen slots is a cheap first try (its failure
  // ends early: the residual of a row it cannot move stops decreasing).
  if (!frozen)
    ++failures_;
  // Stuck at a least-squares minimum with a residual left (J^T r = 0):
  // the constraints conflict there. Otherwise the iteration just failed.
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  if (res(x, r) && jac(x, J) && r.allFinite() && J.allFinite()) {
    double g = (J.transpose() * r).norm();
    if (g <= 1e-8 * std::max(J.norm(), 1e-300) * r.norm())
      stationaryFailure_ = true;
  }
  return false;
}

// Gauss–Newton and tangent directions work in scaled coordinates x = D y,
// each slot in units of its size at the point (its nominal value where
// it is 0), and each constraint in units of its largest term: Andrews'
// squeezer has moments of inertia of 1e-5 beside forces of 1e3, and its
// acceleration constraints divide by the former. Unscaled, minimum-norm
// steps move the tiny unknowns by huge relative amounts and stall,
// round-off in the large terms reads as a residual left, and a rank
// decision takes constraints of small units for tangent directions.
void Sga::scaling(const Point &p, size_t count, Eigen::VectorXd &D,
                  Eigen::VectorXd &weight, Eigen::MatrixXd &J) {
  const Eigen::Index ns = p.x.size();
  D.resize(ns);
  for (Eigen::Index s = 0; s < ns; ++s) {
    double nominal = std::abs(
        m_.variables[out_.form.slots[static_cast<size_t>(s)].var].nominal);
    const double size = std::abs(p.x[s]);
    D[s] = assigned_[static_cast<size_t>(s)]
               ? (size > 1e-8 * nominal ? size : nominal)
               : std::max(size, nominal);
    if (!(D[s] > 0) || !std::isfinite(D[s]))
      D[s] = 1;
  }
  weight = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(count));
  if (!jacobianAt(p, count, J) || !J.allFinite()) {
    J.resize(0, 0);
    return;
  }
  for (Eigen::Index c = 0; c < J.rows(); ++c) {
    double w = (J.row(c).cwiseAbs().cwiseProduct(D.transpose())).maxCoeff();
    weight[c] = w > 1e-300 ? w : 1.0;
  }
  J = weight.cwiseInverse().asDiagonal() * J * D.asDiagonal();
}

// As consistent initialization solves a mechanism: positions from the
// position constraints, then the velocities (linear) from the velocity
// constraints with the positions kept, then the multipliers (linear)
// with both kept. All at once, the minimum-norm steps from a moved
// 50-link chain converged only linearly (the tensions' constraints nearly
// singular along the way) and gave up at 1e-6.
bool Sga::projectByGeneration(Point &p, size_t count) {
  const Point start = p;
  std::vector<char> frozen(static_cast<size_t>(p.x.size()), 0);
  for (size_t done = 0; done < count;) {
    size_t end = done;
    while (end < count && out_.constraints[end].generation ==
                              out_.constraints[done].generation)
      ++end;
    // Each constraint of the generation must read a slot that may move.
    bool movable = true;
    for (size_t c = done; c < end && movable; ++c) {
      bool any = false;
      for (auto [s, g] : gradients_[c])
        any = any || !frozen[static_cast<size_t>(s)];
      movable = any;
    }
    bool ok = movable &&
              (done == 0 ? project(p, end, nullptr) : project(p, end, &frozen));
    if (!ok) {
      if (done == 0)
        return false; // a plain projection already
      p = start;
      return project(p, count);
    }
    for (size_t c = done; c < end; ++c)
      for (auto [s, g] : gradients_[c])
        frozen[static_cast<size_t>(s)] = 1;
    done = end;
  }
  return true;
}

bool Sga::jacobianAt(const Point &p, size_t count, Eigen::MatrixXd &J) {
  ir::EvalEnv env = layout_->env(p);
  J.setZero(static_cast<Eigen::Index>(count), p.x.size());
  bool ok = true;
  for (size_t c = 0; c < count; ++c)
    for (auto [s, g] : gradients_[c])
      J(static_cast<Eigen::Index>(c), s) = valueAt(g, env, ok);
  return ok;
}

bool Sga::definedAt(const Point &p) {
  ir::EvalEnv env = layout_->env(p);
  bool ok = true;
  for (const SgaRow &row : out_.rows)
    valueAt(row.residual, env, ok);
  return ok;
}

void Sga::findAssignments() {
  std::vector<ir::ExprRef> defining;
  for (const SgaRow &row : out_.rows) {
    bool algebraic = row.constraint < 0;
    for (ir::VarKey k : ir::freeVariables(row.residual))
      algebraic = algebraic && layout_->column(k) < 0;
    if (algebraic)
      defining.push_back(row.residual);
  }
  // The slots each equation could assign: without a start value, linear
  // with a coefficient that reads no slot.
  ir::EvalEnv env = layout_->env(Point{t0_, Eigen::VectorXd()});
  std::vector<std::vector<Assignment>> options(defining.size());
  for (size_t e = 0; e < defining.size(); ++e)
    for (ir::VarKey k : ir::freeVariables(defining[e])) {
      int s = layout_->slot(k);
      if (s < 0 || (k.order == 0 && m_.variables[k.var].hasStart))
        continue;
      ir::ExprRef c = diff_.partial(defining[e], k);
      if (!ir::freeVariables(c).empty() || ir::dependsOnTime(c))
        continue;
      bool ok = true;
      double value = valueAt(c, env, ok);
      if (ok && value != 0)
        options[e].push_back({defining[e], s, value});
    }
  // Equations with one choice claim it first (`cobe = cos(q[1])` claims
  // cobe before a loop equation linear in cobe could).
  std::vector<char> &claimed = assigned_;
  claimed.assign(out_.form.slots.size(), 0);
  for (int pass = 0; pass < 2; ++pass)
    for (const std::vector<Assignment> &opts : options) {
      if (opts.empty() || (pass == 0 && opts.size() > 1))
        continue;
      for (const Assignment &a : opts)
        if (!claimed[static_cast<size_t>(a.slot)]) {
          claimed[static_cast<size_t>(a.slot)] = 1;
          assignments_.push_back(a);
          break;
        }
    }
}

void Sga::assignUnstarted(Point &p) {
  // Each sweep settles one more level of the equations' dependencies;
  // an assignment whose inputs are still undefined waits for a later one.
  for (size_t sweep = 0; sweep <= assignments_.size(); ++sweep) {
    bool settled = true;
    ir::EvalEnv env = layout_->env(p);
    for (const Assignment &a : assignments_) {
      bool ok = true;
      double r = valueAt(a.residual, env, ok);
      if (!ok) {
        settled = false;
        continue;
      }
      double &x = p.x[a.slot];
      const double next = x - r / a.coefficient;
      settled =
          settled && std::abs(next - x) <= 1e-14 * std::max(1.0, std::abs(x));
      x = next;
    }
    if (settled)
      return;
  }
}

// The start values are where the modeller says the system is: for a
// mechanism, an assembled configuration that random draws (which scatter
// every angle) almost never find again. From there (the unknowns without
// a start value computed from their equations first, as initialization
// would), or from the point of the previous step (on fewer constraints),
// Gauss–Newton has little to do.
Point Sga::startPoint() {
  const size_t ns = out_.form.slots.size();
  Point given;
  given.t = t0_;
  given.x.resize(static_cast<Eigen::Index>(ns));
  for (size_t i = 0; i < ns; ++i) {
    ir::VarKey k = out_.form.slots[i];
    given.x[static_cast<Eigen::Index>(i)] =
        k.order == 0 ? m_.variables[k.var].start : 0.0;
  }
  assignUnstarted(given);
  return given;
}

bool Sga::findAnchor() {
  const size_t ns = out_.form.slots.size();
  Point given = startPoint();
  const size_t count = out_.constraints.size();
  auto accept = [&](Point &p) {
    anchor_ = std::move(p);
    anchorHolds_ = count;
    anchorDrawn_ = false;
    return true;
  };
  std::vector<Point> starts;
  if (anchor_ && !anchorDrawn_) {
    // What the anchor already meets stays, as in initialization: only the
    // slots the earlier constraints do not read move (the multipliers for
    // acceleration constraints, the velocities for velocity ones). Moving
    // everything, the minimum-norm steps bent a 50-link chain to reach
    // its tensions and did not converge.
    const size_t held = std::min(anchorHolds_, count);
    std::vector<char> frozen(ns, 0);
    for (size_t c = 0; c < held; ++c)
      for (auto [s, g] : gradients_[c])
        frozen[static_cast<size_t>(s)] = 1;
    Point p = *anchor_;
    if (held > 0 && held < count &&
        std::find(frozen.begin(), frozen.end(), 0) != frozen.end() &&
        project(p, count, &frozen) && definedAt(p))
      return accept(p);
    starts.push_back(*anchor_);
  }
  starts.push_back(std::move(given));
  for (Point &p : starts)
    if (project(p, count) && definedAt(p))
      return accept(p);
  return false;
}

/// The anchor displaced along the constraints (a random direction of
/// their tangent space, in slots scaled by their magnitude or nominal
/// value, of kPerturbSpread in the largest) and in time, then projected
/// back. Off the tangent space a mechanism's loop equations pull the point
/// far (0.2 rad on every angle of Andrews' squeezer, and Gauss–Newton
/// does not return); along it the step is off the manifold only to second
/// order. Each point gets its own time, so time-dependent entries are
/// generic too.
bool Sga::perturbAnchor(Point &p, int index) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Index ns = anchor_->x.size();
  Eigen::VectorXd scale, weight;
  Eigen::MatrixXd J;
  scaling(*anchor_, out_.constraints.size(), scale, weight, J);
  Eigen::MatrixXd tangent = Eigen::MatrixXd::Identity(ns, ns);
  if (J.rows() > 0 && ns > 0) {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullV);
    const Eigen::VectorXd &sv = svd.singularValues();
    Eigen::Index rank = 0;
    while (rank < sv.size() && sv[rank] > kRankTol * sv[0])
      ++rank;
    tangent = svd.matrixV().rightCols(ns - rank);
  }
  const size_t count = out_.constraints.size();
  bool timeDependent = false;
  for (const SgaConstraintExpr &c : out_.constraints)
    timeDependent = timeDependent || ir::dependsOnTime(c.expr);
  // How far a point is off the constraints, in the units of each.
  auto offBy = [&](const Point &q) {
    ir::EvalEnv env = layout_->env(q);
    double worst = 0;
    for (size_t c = 0; c < count; ++c) {
      bool ok = true;
      double v = valueAt(out_.constraints[c].expr, env, ok);
      if (!ok)
        return std::numeric_limits<double>::infinity();
      worst =
          std::max(worst, std::abs(v) / weight[static_cast<Eigen::Index>(c)]);
    }
    return worst;
  };
  double spread = kPerturbSpread;
  for (int attempt = 0; attempt < kPerturbAttempts; ++attempt, spread *= 0.25) {
    p = *anchor_;
    if (tangent.cols() > 0) {
      Eigen::VectorXd w(tangent.cols());
      for (Eigen::Index k = 0; k < w.size(); ++k)
        w[k] = normal(rng_);
      Eigen::VectorXd dy = tangent * w;
      const double largest = dy.cwiseAbs().maxCoeff();
      // Shorter while the move leaves the manifold by more than
      // kTangentOff: a 50-link chain's end moves by 20% of its distance
      // from the origin, six link lengths, along a tangent that holds
      // to first order only. Judged by one evaluation each, not by
      // failed projections.
      double step = largest > 0 ? spread / largest : 0.0;
      for (int h = 0; h < kTangentHalvings; ++h, step *= 0.5) {
        p.x = anchor_->x + step * scale.cwiseProduct(dy);
        if (offBy(p) <= kTangentOff)
          break;
      }
    }
    if (!projectByGeneration(p, count))
      continue;
    // Then along time, in steps that each projection starts close to
    // (the car axis's road bump, r sin(10 t), turns by at most 2 rad in
    // each; in one jump Gauss–Newton lost its acceleration constraints).
    const double t1 = anchor_->t + 0.3 + 0.25 * index + 0.1 * u(rng_);
    const double from = p.t;
    bool followed = true;
    for (int k = 1; timeDependent && k <= kTimeSteps && followed; ++k) {
      p.t = from + (t1 - from) * k / kTimeSteps;
      followed = projectByGeneration(p, count);
    }
    p.t = t1;
    if (followed && definedAt(p))
      return true;
  }
  return false;
}

/// The fallback: a random point near the start values, projected.
bool Sga::drawPoint(Point &p, int index) {
  const size_t ns = out_.form.slots.size();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int attempt = 0; attempt < kDrawAttempts; ++attempt) {
    p.t = t0_ + 0.3 + 0.25 * index + 0.1 * u(rng_);
    p.x.resize(static_cast<Eigen::Index>(ns));
    // Generic points near the start values; closer ones after failures
    // (a mechanism's constraints from far away may not be reachable).
    const double spread = 0.8 * std::pow(0.2, attempt);
    for (size_t i = 0; i < ns; ++i) {
      ir::VarKey k = out_.form.slots[i];
      const ir::Variable &var = m_.variables[k.var];
      double base = k.order == 0 ? var.start : 0.0;
      double scale = std::max(std::abs(var.nominal), 1e-300);
      p.x[static_cast<Eigen::Index>(i)] =
          base + scale * spread * (0.6 * u(rng_) + (u(rng_) > 0 ? 0.4 : -0.4));
    }
    if (project(p, out_.constraints.size()) && definedAt(p))
      return true;
  }
  return false;
}

bool Sga::samplePoints(std::vector<Point> &pts, bool draw) {
  pts.assign(kPoints, Point{});
  const bool anchored = findAnchor();
  for (int s = 0; s < kPoints; ++s)
    if (!(anchored && perturbAnchor(pts[static_cast<size_t>(s)], s)) &&
        !(draw && drawPoint(pts[static_cast<size_t>(s)], s)))
      return false;
  if (!anchored) {
    anchor_ = pts.front();
    anchorHolds_ = out_.constraints.size();
    anchorDrawn_ = true;
  }
  return true;
}

bool Sga::holds(ir::ExprRef phi, const std::vector<Point> &pts, double scale) {
  for (const Point &p : pts) {
    bool ok = true;
    double v = valueAt(phi, layout_->env(p), ok);
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
  std::vector<std::pair<int, ir::ExprRef>> grad;
  for (ir::VarKey k : ir::freeVariables(phi)) {
    int s = layout_->slot(k);
    if (s >= 0)
      grad.emplace_back(s, diff_.partial(phi, k));
  }
  gradients_.push_back(std::move(grad));
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
      int c = layout_->column(k);
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
    ir::EvalEnv env = layout_->env(pts[s]);
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
    if (!inOrder)
      return;
    if (hi - lo < 2) {
      inOrder = hi == lo;
      return;
    }
    const size_t ncons = out_.constraints.size(), nrows = out_.rows.size();
    for (size_t k = lo; k < hi; ++k)
      addConstraint(rows[fresh[k]].rem, rows[fresh[k]].sources);
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
    out_.constraints.resize(ncons);
    gradients_.resize(ncons);
    out_.rows.resize(nrows);
    anchorHolds_ = std::min(anchorHolds_, ncons);
    const size_t mid = lo + (hi - lo) / 2;
    addChunk(lo, mid);
    addChunk(mid, hi);
  };
  addChunk(0, fresh.size());
  for (int i : candidates) {
    if (batched.count(i))
      continue;
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
    stationaryFailure_ = false;
    if (!samplePoints(pts)) {
      if (!stationaryFailure_) {
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
      out_.constraints.pop_back();
      out_.rows.pop_back();
      gradients_.pop_back();
      anchorHolds_ = std::min(anchorHolds_, out_.constraints.size());
      if (!samplePoints(pts))
        return false;
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
  jacobianAt(p, ncons, J);
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
  const auto allGradients = gradients_;
  const std::optional<Point> anchor = anchor_; // on all of them
  const size_t anchorHolds = anchorHolds_;
  for (size_t c = 0; c < all.size(); ++c) {
    if (all[c].generation != 0 || all[c].sources.size() != 1)
      continue;
    const int e = all[c].sources.front();
    for (const SgaConstraintExpr &phi : implied_) {
      if (std::binary_search(phi.sources.begin(), phi.sources.end(), e))
        continue;
      out_.constraints.clear();
      gradients_.clear();
      for (size_t k = 0; k < all.size(); ++k)
        if (k != c) {
          out_.constraints.push_back(all[k]);
          gradients_.push_back(allGradients[k]);
        }
      const size_t rowsBefore = out_.rows.size();
      // All but c: the anchor meets them.
      anchorHolds_ = out_.constraints.size();
      addConstraint(phi.expr, phi.sources);
      out_.rows.resize(rowsBefore);
      std::vector<Point> pts;
      bool implied = samplePoints(pts) && holds(all[c].expr, pts, 1.0);
      out_.constraints = all;
      gradients_ = allGradients;
      anchor_ = anchor;
      anchorHolds_ = anchorHolds;
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
  layout_ = std::make_unique<Layout>(m_, out_.form);
  for (int e : mr_.equations) {
    SgaRow row;
    row.residual = m_.equations[e].residual;
    row.sources = {e};
    out_.rows.push_back(row);
  }
  findAssignments();
  const Point given = startPoint();
  out_.startGuess.assign(given.x.data(), given.x.data() + given.x.size());
  std::vector<Point> pts;
  if (!samplePoints(pts)) {
    out_.ran = false;
    out_.skipped = "no point where every equation is defined was found";
    return;
  }
  const size_t maxSteps = out_.form.slots.size() + 2;
  for (size_t k = 0; k < maxSteps; ++k) {
    ++out_.steps;
    bool grew = false;
    if (!step(pts, grew)) {
      if (undecided_) {
        out_.ran = false;
        out_.skipped = "no point satisfying the constraints was found from "
                       "the start values (Gauss-Newton did not converge)";
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
