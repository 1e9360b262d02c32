// Points on a manifold given by equations over a model's variables and
// their derivatives: the sample points at which the SGA (Sga.cpp) and the
// formal index (FormalIndex.cpp) decide ranks numerically. An anchor is
// reached from the start values (unknowns without a start value computed
// from the equations that define them), kept from one call to the next
// while the equations grow, and moved along random tangent directions and
// in time, then projected back by Gauss–Newton in nominal-scaled units;
// random points near the start values are the fallback. docs/sga.md,
// "Counting", says why each part is there.
#pragma once

#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Model.h"

#include <Eigen/Dense>

#include <cstddef>
#include <functional>
#include <optional>
#include <random>
#include <utility>
#include <vector>

namespace ldae::passes {

/// The value of `e` in `env`; `ok` becomes false when it cannot be
/// evaluated or is not finite.
double valueAt(ir::ExprRef e, const ir::EvalEnv &env, bool &ok);

struct SamplePoint {
  double t = 0;
  Eigen::VectorXd x; // one value per coordinate
};

/// One equation phi(t, x) = 0 of the manifold, with the coordinates it
/// reads and its partial derivatives with respect to them.
struct SampledEquation {
  ir::ExprRef expr = nullptr;
  /// Projections move a generation at a time (docs/sga.md): positions,
  /// then velocities with the positions kept, and so on.
  int generation = 0;
  std::vector<std::pair<int, ir::ExprRef>> gradient;
  /// Nodes an evaluation of expr, and of the whole gradient, visits (each
  /// entry is evaluated on its own): what the budget counts.
  double exprNodes = 0, gradientNodes = 0;
};

class ManifoldSampler {
public:
  /// Coordinates are variables of `model` at some derivative order; any
  /// other variable evaluates to 0 (a discrete one to its start value).
  ManifoldSampler(const ir::Model &model, ir::Differentiator &diff,
                  std::vector<ir::VarKey> coordinates);

  // --- coordinates
  const std::vector<ir::VarKey> &coordinates() const { return coords_; }
  int coordinate(ir::VarKey k) const;
  /// Appends coordinates; the anchor gets 0 there (not yet on equations
  /// that read them).
  void addCoordinates(const std::vector<ir::VarKey> &keys);
  /// The environment of `p` (time, coordinates, parameters).
  ir::EvalEnv env(const SamplePoint &p) const;

  // --- equations (the caller adds and removes them as its manifold grows)
  std::vector<SampledEquation> &equations() { return eqs_; }
  const std::vector<SampledEquation> &equations() const { return eqs_; }
  /// Appends phi = 0, its gradient taken symbolically.
  void addEquation(ir::ExprRef phi, int generation);
  /// Keeps the first `count` equations.
  void truncate(size_t count);

  // --- the start point
  /// Equations that compute an unknown without a start value: those of
  /// `defining` linear in a coordinate without a start value (derivatives
  /// have none), with a constant coefficient (`lang = sqrt(...)`, `cobe =
  /// cos(q[1])`).
  void findAssignments(const std::vector<ir::ExprRef> &defining);
  /// The start values at the start time, order >= 1 at 0, the unknowns
  /// without a start value computed by the assignments.
  SamplePoint startPoint();

  // --- points
  /// `count` points on all equations: perturbations of the anchor, else
  /// (with `draw`) random draws near the start values. `acceptable` (if
  /// set) must hold at each.
  bool samplePoints(std::vector<SamplePoint> &pts, int count, bool draw = true);
  /// Onto the first `count` equations; coordinates marked in `frozen`
  /// stay.
  bool project(SamplePoint &p, size_t count,
               const std::vector<char> *frozen = nullptr);
  /// The first `count` equations' Jacobian at p.
  bool jacobianAt(const SamplePoint &p, size_t count, Eigen::MatrixXd &J);
  /// Whether every equation (and `acceptable`) holds a value at p.
  bool definedAt(const SamplePoint &p);
  /// What else a sample point must satisfy (the SGA: every row can be
  /// evaluated there).
  std::function<bool(const SamplePoint &)> acceptable;

  // --- the anchor, kept between calls
  struct AnchorState {
    std::optional<SamplePoint> anchor;
    size_t holds = 0; // it meets equations [0, holds)
    bool drawn = false;
  };
  const AnchorState &anchorState() const { return anchor_; }
  void setAnchorState(AnchorState s) { anchor_ = std::move(s); }
  /// The anchor meets at most the first `count` equations.
  void limitAnchorHolds(size_t count);
  /// The anchor meets every equation now (they were set so).
  void anchorMeetsAll() { anchor_.holds = eqs_.size(); }

  // --- budgets and diagnosis
  /// Failed projections before every further one fails at once: each
  /// costs at most 40 Gauss–Newton steps, so giving up costs a bounded
  /// multiple of one projection, not seconds of random draws (Andrews'
  /// squeezer spent up to 2.5 s so in the SGA before it had anchors).
  int failureBudget = 24;
  /// Floating-point operations the Jacobians' solves may cost in all
  /// (rows x cols x min(rows, cols) each); 0: unlimited. Counted, not
  /// timed, so the answer does not depend on the machine.
  double workBudget = 0;
  double work() const { return work_; }
  /// Expression nodes the projections may evaluate in all (residuals and
  /// Jacobian entries); 0: unlimited. Differentiation can make the
  /// equations of a later generation huge (a mutated Andrews' squeezer's
  /// gradients ran for minutes): this bounds that, counted likewise.
  double evaluationBudget = 0;
  double evaluations() const { return evaluations_; }
  bool exhausted() const {
    return failures_ >= failureBudget ||
           (workBudget > 0 && work_ > workBudget) ||
           (evaluationBudget > 0 && evaluations_ > evaluationBudget);
  }
  /// A projection ended at a least-squares minimum off the equations
  /// since the last reset (the equations conflict there).
  bool stationaryFailure = false;
  /// Whether a failed projection looks for that (one more Jacobian).
  bool diagnoseFailures = true;

private:
  const ir::Model &m_;
  ir::Differentiator &diff_;
  std::vector<ir::VarKey> coords_;
  std::vector<std::vector<int>> index_; // [var][order] -> coordinate, -1
  std::vector<double> params_;
  std::vector<SampledEquation> eqs_;
  std::mt19937 rng_;
  double t0_;
  AnchorState anchor_;
  int failures_ = 0;
  double work_ = 0;
  double evaluations_ = 0;
  struct Assignment {
    ir::ExprRef residual;
    int coordinate;
    double coefficient;
  };
  std::vector<Assignment> assignments_;
  std::vector<char> assigned_; // per coordinate: computed by an assignment

  void assignUnstarted(SamplePoint &p);
  bool findAnchor();
  bool perturbAnchor(SamplePoint &p, int index);
  bool drawPoint(SamplePoint &p, int index);
  /// Coordinate scales D, equation weights and the scaled Jacobian
  /// W^-1 J D at p (empty when J cannot be evaluated there).
  void scaling(const SamplePoint &p, size_t count, Eigen::VectorXd &D,
               Eigen::VectorXd &weight, Eigen::MatrixXd &J);
  bool projectByGeneration(SamplePoint &p, size_t count);
  /// One Gauss–Newton projection in the units of p's start.
  bool projectScaled(SamplePoint &p, size_t count,
                     const std::vector<char> *frozen);
  double rescaled_ = 0; // largest scaled coordinate it ended at
  double residual_ = 0; // largest weighted residual it ended at
};

} // namespace ldae::passes
