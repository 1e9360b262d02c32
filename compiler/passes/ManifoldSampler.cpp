// Sample points on a manifold (ManifoldSampler.h): the anchor, its
// tangent moves and the scaled Gauss–Newton projections. Found for the
// SGA on mechanisms (Andrews' squeezer, a 50-link chain, the car axis)
// and shared with the formal index, whose prolonged systems are the same
// kind of manifold in more coordinates.
#include "passes/ManifoldSampler.h"

#include "ir/Query.h"
#include "numeric/Newton.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldae::passes {

namespace {

constexpr int kDrawAttempts = 5; // random draws per point (the fallback)
/// Sample points are the anchor (a point of the manifold reached from the
/// start values) displaced by this fraction of each coordinate's scale and
/// projected back: large enough that ranks there are generic, small
/// enough that Gauss–Newton comes back. Quartered after a failure.
constexpr double kPerturbSpread = 0.2;
constexpr int kPerturbAttempts = 3;
/// A tangent move is halved (up to kTangentHalvings times) until the
/// equations are off by at most kTangentOff of their units there.
constexpr double kTangentOff = 0.05;
constexpr int kTangentHalvings = 16;
/// Steps from the anchor's time to a sample point's when the equations
/// depend on time (a continuation: each projection starts close).
constexpr int kTimeSteps = 4;
constexpr double kRankTol = 1e-9; // singular values below count as 0
/// A converged projection is repeated in the units of where it ended
/// (up to kRescales times) when a coordinate ended kRescaleAbove of its
/// units from 0, or an equation is off by more than kProjected of its
/// largest term.
constexpr double kRescaleAbove = 1e3;
constexpr double kProjected = 1e-10;
constexpr int kRescales = 4;

} // namespace

double valueAt(ir::ExprRef e, const ir::EvalEnv &env, bool &ok) {
  auto v = ir::evaluate(e, env);
  if (!v || !std::isfinite(*v)) {
    ok = false;
    return 0;
  }
  return *v;
}

ManifoldSampler::ManifoldSampler(const ir::Model &model,
                                 ir::Differentiator &diff,
                                 std::vector<ir::VarKey> coordinates)
    : m_(model), diff_(diff), params_(model.parameterValues()), rng_(20261124),
      t0_(model.experiment.startTime.value_or(0.0)) {
  addCoordinates(coordinates);
}

int ManifoldSampler::coordinate(ir::VarKey k) const {
  // Every evaluation asks for every variable it reads: a lookup in a
  // table, not a map (5% of the formal index of Andrews' squeezer).
  if (k.var >= index_.size() || k.order >= index_[k.var].size())
    return -1;
  return index_[k.var][k.order];
}

void ManifoldSampler::addCoordinates(const std::vector<ir::VarKey> &keys) {
  for (ir::VarKey k : keys) {
    if (k.var >= index_.size())
      index_.resize(k.var + 1);
    std::vector<int> &orders = index_[k.var];
    if (k.order >= orders.size())
      orders.resize(k.order + 1, -1);
    orders[k.order] = static_cast<int>(coords_.size());
    coords_.push_back(k);
  }
  assigned_.resize(coords_.size(), 0);
  if (anchor_.anchor) {
    Eigen::VectorXd &x = anchor_.anchor->x;
    const Eigen::Index old = x.size();
    x.conservativeResize(static_cast<Eigen::Index>(coords_.size()));
    x.tail(x.size() - old).setZero();
  }
}

ir::EvalEnv ManifoldSampler::env(const SamplePoint &p) const {
  ir::EvalEnv e;
  e.time = p.t;
  e.variable = [this, &p](ir::VarKey k) {
    int c = coordinate(k);
    if (c >= 0)
      return c < p.x.size() ? p.x[c] : 0.0;
    // Discrete variables keep their start value between events.
    if (k.order == 0 && k.var < m_.variables.size())
      return m_.variables[k.var].start;
    return 0.0;
  };
  e.parameter = [this](ir::ParamId q) {
    return q < params_.size() ? params_[q] : 0.0;
  };
  return e;
}

void ManifoldSampler::addEquation(ir::ExprRef phi, int generation) {
  SampledEquation eq{phi, generation, {}};
  for (ir::VarKey k : ir::freeVariables(phi)) {
    int c = coordinate(k);
    if (c >= 0)
      eq.gradient.emplace_back(c, diff_.partial(phi, k));
  }
  eq.exprNodes = double(ir::dagSize(phi));
  for (const auto &[c, g] : eq.gradient)
    eq.gradientNodes += double(ir::dagSize(g));
  // Building the gradient is charged to the same budget: each partial
  // derivative walks the whole equation. A mutated Andrews' squeezer
  // (der(der(v[6]))) spent 8 s of CPU differentiating and re-adding the
  // halves of one generation whose projections alone stayed within it.
  evaluations_ += eq.exprNodes * double(eq.gradient.size()) + eq.gradientNodes;
  eqs_.push_back(std::move(eq));
}

void ManifoldSampler::truncate(size_t count) {
  if (count < eqs_.size())
    eqs_.resize(count);
  limitAnchorHolds(count);
}

void ManifoldSampler::limitAnchorHolds(size_t count) {
  anchor_.holds = std::min(anchor_.holds, count);
}

void ManifoldSampler::findAssignments(
    const std::vector<ir::ExprRef> &defining) {
  // The coordinates each equation could assign: without a start value
  // (derivatives have none), linear with a coefficient that reads no
  // coordinate.
  ir::EvalEnv env = this->env(SamplePoint{t0_, Eigen::VectorXd()});
  std::vector<std::vector<Assignment>> options(defining.size());
  for (size_t e = 0; e < defining.size(); ++e)
    for (ir::VarKey k : ir::freeVariables(defining[e])) {
      int c = coordinate(k);
      if (c < 0 || (k.order == 0 && m_.variables[k.var].hasStart))
        continue;
      ir::ExprRef a = diff_.partial(defining[e], k);
      if (!ir::freeVariables(a).empty() || ir::dependsOnTime(a))
        continue;
      bool ok = true;
      double value = valueAt(a, env, ok);
      if (ok && value != 0)
        options[e].push_back({defining[e], c, value});
    }
  // Equations with one choice claim it first (`cobe = cos(q[1])` claims
  // cobe before a loop equation linear in cobe could).
  assignments_.clear();
  assigned_.assign(coords_.size(), 0);
  for (int pass = 0; pass < 2; ++pass)
    for (const std::vector<Assignment> &opts : options) {
      if (opts.empty() || (pass == 0 && opts.size() > 1))
        continue;
      for (const Assignment &a : opts)
        if (!assigned_[static_cast<size_t>(a.coordinate)]) {
          assigned_[static_cast<size_t>(a.coordinate)] = 1;
          assignments_.push_back(a);
          break;
        }
    }
}

void ManifoldSampler::assignUnstarted(SamplePoint &p) {
  // Each sweep settles one more level of the equations' dependencies;
  // an assignment whose inputs are still undefined waits for a later one.
  for (size_t sweep = 0; sweep <= assignments_.size(); ++sweep) {
    bool settled = true;
    ir::EvalEnv e = env(p);
    for (const Assignment &a : assignments_) {
      bool ok = true;
      double r = valueAt(a.residual, e, ok);
      if (!ok) {
        settled = false;
        continue;
      }
      double &x = p.x[a.coordinate];
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
// would), or from the point of the previous call (on fewer equations),
// Gauss–Newton has little to do.
SamplePoint ManifoldSampler::startPoint() {
  const size_t n = coords_.size();
  SamplePoint given;
  given.t = t0_;
  given.x.resize(static_cast<Eigen::Index>(n));
  for (size_t i = 0; i < n; ++i) {
    ir::VarKey k = coords_[i];
    given.x[static_cast<Eigen::Index>(i)] =
        k.order == 0 ? m_.variables[k.var].start : 0.0;
  }
  assignUnstarted(given);
  return given;
}

bool ManifoldSampler::project(SamplePoint &p, size_t count,
                              const std::vector<char> *frozen) {
  if (count == 0)
    return true;
  if (exhausted())
    return false;
  // The scales are taken at the start: a projection that moves a
  // coordinate far beyond its scale (a new derivative of a prolongation
  // from 0 to 1e6) converged in units too coarse for the others, the test
  // being relative to the largest scaled coordinate. Again from there, in
  // the units of where it ended.
  for (int round = 0;; ++round) {
    if (!projectScaled(p, count, frozen))
      return false;
    if (round == kRescales ||
        !(rescaled_ > kRescaleAbove || residual_ > kProjected))
      return true;
  }
}

bool ManifoldSampler::projectScaled(SamplePoint &p, size_t count,
                                    const std::vector<char> *frozen) {
  ir::EvalEnv e = env(p);
  Eigen::VectorXd D, weight;
  Eigen::MatrixXd J0;
  scaling(p, count, D, weight, J0);
  // Gauss–Newton runs on the coordinates that move only: the held ones'
  // columns would cost as much to decompose as they are many (a
  // prolongation's new coordinates are a sixth of Andrews' 462).
  std::vector<Eigen::Index> moving;
  for (Eigen::Index s = 0; s < p.x.size(); ++s)
    if (!frozen || !(*frozen)[static_cast<size_t>(s)])
      moving.push_back(s);
  const Eigen::Index nm = static_cast<Eigen::Index>(moving.size());
  Eigen::VectorXd scaled = p.x.cwiseQuotient(D);
  auto place = [&](const Eigen::VectorXd &z) {
    for (Eigen::Index k = 0; k < nm; ++k)
      scaled[moving[static_cast<size_t>(k)]] = z[k];
    p.x = D.cwiseProduct(scaled);
  };
  numeric::ResidualFn res = [&](const Eigen::VectorXd &z, Eigen::VectorXd &r) {
    place(z);
    r.resize(static_cast<Eigen::Index>(count));
    bool ok = true;
    for (size_t c = 0; c < count; ++c) {
      r[static_cast<Eigen::Index>(c)] = valueAt(eqs_[c].expr, e, ok);
      evaluations_ += eqs_[c].exprNodes;
    }
    r = r.cwiseQuotient(weight);
    return ok;
  };
  numeric::JacobianFn jac = [&](const Eigen::VectorXd &z, Eigen::MatrixXd &J) {
    if (exhausted())
      return false;
    place(z);
    Eigen::MatrixXd all;
    bool ok = jacobianAt(p, count, all);
    J.resize(all.rows(), nm);
    for (Eigen::Index k = 0; k < nm; ++k) {
      const Eigen::Index s = moving[static_cast<size_t>(k)];
      J.col(k) = all.col(s) * D[s];
    }
    J = weight.cwiseInverse().asDiagonal() * J;
    work_ += double(J.rows()) * double(J.cols()) *
             double(std::min(J.rows(), J.cols()));
    return ok;
  };
  numeric::NewtonOptions opts;
  // Round-off in equations with large terms (a mechanism's forces) keeps
  // residuals well above 1e-13 of the coordinates.
  opts.tolerance = 1e-10;
  opts.maxIterations = 40;
  opts.backtrack = true;
  Eigen::VectorXd x(nm);
  for (Eigen::Index k = 0; k < nm; ++k)
    x[k] = scaled[moving[static_cast<size_t>(k)]];
  numeric::NewtonResult nr = numeric::gaussNewton(res, jac, x, opts);
  place(x);
  if (nr.converged()) {
    // The test above is relative to the largest coordinate (a spring
    // force of 2000 N beside angles), looser than the SGA judges each
    // constraint: two more steps, quadratically convergent, close the gap
    // (none where the residual is at rounding level already).
    numeric::NewtonOptions polish = opts;
    polish.tolerance = 1e-15;
    polish.maxIterations = 2;
    Eigen::VectorXd converged = x;
    if (numeric::gaussNewton(res, jac, x, polish).status ==
        numeric::NewtonStatus::EvaluationFailed)
      x = converged;
    place(x);
    rescaled_ = nm > 0 ? x.cwiseAbs().maxCoeff() : 0.0;
    Eigen::VectorXd r;
    residual_ = res(x, r) && r.size() > 0 ? r.cwiseAbs().maxCoeff() : 0.0;
    return true;
  }
  // A projection with frozen coordinates is a cheap first try (its
  // failure ends early: the residual of a row it cannot move stops
  // decreasing).
  if (!frozen)
    ++failures_;
  // Stuck at a least-squares minimum with a residual left (J^T r = 0):
  // the equations conflict there. Otherwise the iteration just failed.
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  if (diagnoseFailures && res(x, r) && jac(x, J) && r.allFinite() &&
      J.allFinite()) {
    double g = (J.transpose() * r).norm();
    if (g <= 1e-8 * std::max(J.norm(), 1e-300) * r.norm())
      stationaryFailure = true;
  }
  return false;
}

// Gauss–Newton and tangent directions work in scaled coordinates x = D y,
// each coordinate in units of its size at the point (its nominal value
// where it is 0), and each equation in units of its largest term:
// Andrews' squeezer has moments of inertia of 1e-5 beside forces of 1e3,
// and its acceleration constraints divide by the former. Unscaled,
// minimum-norm steps move the tiny unknowns by huge relative amounts and
// stall, round-off in the large terms reads as a residual left, and a
// rank decision takes equations of small units for tangent directions.
void ManifoldSampler::scaling(const SamplePoint &p, size_t count,
                              Eigen::VectorXd &D, Eigen::VectorXd &weight,
                              Eigen::MatrixXd &J) {
  const Eigen::Index n = p.x.size();
  D.resize(n);
  for (Eigen::Index s = 0; s < n; ++s) {
    double nominal =
        std::abs(m_.variables[coords_[static_cast<size_t>(s)].var].nominal);
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
  // No coordinates (a model whose equations read parameters only): no
  // row has a largest entry to scale by.
  for (Eigen::Index c = 0; n > 0 && c < J.rows(); ++c) {
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
bool ManifoldSampler::projectByGeneration(SamplePoint &p, size_t count) {
  const SamplePoint start = p;
  std::vector<char> frozen(static_cast<size_t>(p.x.size()), 0);
  for (size_t done = 0; done < count;) {
    size_t end = done;
    while (end < count && eqs_[end].generation == eqs_[done].generation)
      ++end;
    // Each equation of the generation must read a coordinate that may move.
    bool movable = true;
    for (size_t c = done; c < end && movable; ++c) {
      bool any = false;
      for (auto [s, g] : eqs_[c].gradient)
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
      for (auto [s, g] : eqs_[c].gradient)
        frozen[static_cast<size_t>(s)] = 1;
    done = end;
  }
  return true;
}

bool ManifoldSampler::jacobianAt(const SamplePoint &p, size_t count,
                                 Eigen::MatrixXd &J) {
  ir::EvalEnv e = env(p);
  J.setZero(static_cast<Eigen::Index>(count), p.x.size());
  bool ok = true;
  for (size_t c = 0; c < count; ++c) {
    for (auto [s, g] : eqs_[c].gradient)
      J(static_cast<Eigen::Index>(c), s) = valueAt(g, e, ok);
    evaluations_ += eqs_[c].gradientNodes;
  }
  return ok;
}

bool ManifoldSampler::definedAt(const SamplePoint &p) {
  ir::EvalEnv e = env(p);
  bool ok = true;
  for (const SampledEquation &eq : eqs_)
    valueAt(eq.expr, e, ok);
  return ok && (!acceptable || acceptable(p));
}

bool ManifoldSampler::findAnchor() {
  const size_t n = coords_.size();
  SamplePoint given = startPoint();
  const size_t count = eqs_.size();
  auto accept = [&](SamplePoint &p) {
    anchor_.anchor = std::move(p);
    anchor_.holds = count;
    anchor_.drawn = false;
    return true;
  };
  std::vector<SamplePoint> starts;
  if (anchor_.anchor && !anchor_.drawn) {
    // What the anchor already meets stays, as in initialization: only the
    // coordinates the earlier equations do not read move (the multipliers
    // for acceleration constraints, the velocities for velocity ones).
    // Moving everything, the minimum-norm steps bent a 50-link chain to
    // reach its tensions and did not converge.
    const size_t held = std::min(anchor_.holds, count);
    std::vector<char> frozen(n, 0);
    for (size_t c = 0; c < held; ++c)
      for (auto [s, g] : eqs_[c].gradient)
        frozen[static_cast<size_t>(s)] = 1;
    SamplePoint p = *anchor_.anchor;
    if (held > 0 && held < count &&
        std::find(frozen.begin(), frozen.end(), 0) != frozen.end() &&
        project(p, count, &frozen) && definedAt(p))
      return accept(p);
    starts.push_back(*anchor_.anchor);
  }
  starts.push_back(std::move(given));
  for (SamplePoint &p : starts)
    if (project(p, count) && definedAt(p))
      return accept(p);
  return false;
}

/// The anchor displaced along the equations (a random direction of their
/// tangent space, in coordinates scaled by their magnitude or nominal
/// value, of kPerturbSpread in the largest) and in time, then projected
/// back. Off the tangent space a mechanism's loop equations pull the point
/// far (0.2 rad on every angle of Andrews' squeezer, and Gauss–Newton
/// does not return); along it the step is off the manifold only to second
/// order. Each point gets its own time, so time-dependent entries are
/// generic too.
bool ManifoldSampler::perturbAnchor(SamplePoint &p, int index) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  if (exhausted())
    return false;
  const SamplePoint &anchor = *anchor_.anchor;
  const Eigen::Index n = anchor.x.size();
  const size_t count = eqs_.size();
  Eigen::VectorXd scale, weight;
  Eigen::MatrixXd J;
  scaling(anchor, count, scale, weight, J);
  Eigen::MatrixXd tangent = Eigen::MatrixXd::Identity(n, n);
  if (J.rows() > 0 && n > 0) {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullV);
    work_ += double(J.rows()) * double(n) * double(n);
    const Eigen::VectorXd &sv = svd.singularValues();
    Eigen::Index rank = 0;
    while (rank < sv.size() && sv[rank] > kRankTol * sv[0])
      ++rank;
    tangent = svd.matrixV().rightCols(n - rank);
  }
  bool timeDependent = false;
  for (const SampledEquation &eq : eqs_)
    timeDependent = timeDependent || ir::dependsOnTime(eq.expr);
  // How far a point is off the equations, in the units of each.
  auto offBy = [&](const SamplePoint &q) {
    ir::EvalEnv e = env(q);
    double worst = 0;
    for (size_t c = 0; c < count; ++c) {
      bool ok = true;
      double v = valueAt(eqs_[c].expr, e, ok);
      if (!ok)
        return std::numeric_limits<double>::infinity();
      worst =
          std::max(worst, std::abs(v) / weight[static_cast<Eigen::Index>(c)]);
    }
    return worst;
  };
  double spread = kPerturbSpread;
  for (int attempt = 0; attempt < kPerturbAttempts; ++attempt, spread *= 0.25) {
    p = anchor;
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
        p.x = anchor.x + step * scale.cwiseProduct(dy);
        if (offBy(p) <= kTangentOff)
          break;
      }
    }
    if (!projectByGeneration(p, count))
      continue;
    // Then along time, in steps that each projection starts close to
    // (the car axis's road bump, r sin(10 t), turns by at most 2 rad in
    // each; in one jump Gauss–Newton lost its acceleration constraints).
    const double t1 = anchor.t + 0.3 + 0.25 * index + 0.1 * u(rng_);
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
bool ManifoldSampler::drawPoint(SamplePoint &p, int index) {
  const size_t n = coords_.size();
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int attempt = 0; attempt < kDrawAttempts && !exhausted(); ++attempt) {
    p.t = t0_ + 0.3 + 0.25 * index + 0.1 * u(rng_);
    p.x.resize(static_cast<Eigen::Index>(n));
    // Generic points near the start values; closer ones after failures
    // (a mechanism's constraints from far away may not be reachable).
    const double spread = 0.8 * std::pow(0.2, attempt);
    for (size_t i = 0; i < n; ++i) {
      ir::VarKey k = coords_[i];
      const ir::Variable &var = m_.variables[k.var];
      double base = k.order == 0 ? var.start : 0.0;
      double scale = std::max(std::abs(var.nominal), 1e-300);
      p.x[static_cast<Eigen::Index>(i)] =
          base + scale * spread * (0.6 * u(rng_) + (u(rng_) > 0 ? 0.4 : -0.4));
    }
    if (project(p, eqs_.size()) && definedAt(p))
      return true;
  }
  return false;
}

bool ManifoldSampler::samplePoints(std::vector<SamplePoint> &pts, int count,
                                   bool draw) {
  pts.assign(static_cast<size_t>(count), SamplePoint{});
  const bool anchored = findAnchor();
  for (int s = 0; s < count; ++s)
    if (exhausted() ||
        (!(anchored && perturbAnchor(pts[static_cast<size_t>(s)], s)) &&
         !(draw && drawPoint(pts[static_cast<size_t>(s)], s))))
      return false;
  if (!anchored) {
    anchor_.anchor = pts.front();
    anchor_.holds = eqs_.size();
    anchor_.drawn = true;
  }
  return true;
}

} // namespace ldae::passes
