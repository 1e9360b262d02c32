// Pass "formal-index": Le Vey's index (seed 004, definition 3.8) of the
// system as written (before alias elimination, without reduction to first
// order). The model of order q
// (its highest derivative, at least 1) is a submanifold R_q of the jet space
// J_q whose coordinates are every unknown with its derivatives up to order
// q. Its s-th prolongation R_{q+s} is the equations with their first s
// total time derivatives, over the coordinates up to order q + s; the
// projection R_q^(s) of R_{q+s} back onto J_q holds every equation of order
// <= q that differentiation and elimination can produce. The sets shrink,
// R_q^(s+1) ⊆ R_q^(s); the formal index is the first s at which they stop:
// R_q^(s+1) = R_q^(s) makes R_q^(s) formally integrable (theorem 3.1).
//
// Equal sets are decided by equal dimensions (the second lies in the
// first), and a dimension by ranks: at a point of R_{q+s}, the codimension
// of R_q^(s) in J_q is rank J - rank J_high, J the Jacobian of the prolonged
// equations w.r.t. all coordinates and J_high its columns of order > q
// (numeric/ProjectedRank.h). The point is random: a random start (time
// included) brought onto R_{q+s} by Gauss–Newton; each step takes the
// codimension most of kPoints points agree on. Nothing is decided from
// syntactic zeros. See docs/indices.md.
#include "passes/FormalIndex.h"
#include "passes/Passes.h"

#include "ir/Differentiate.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "numeric/Newton.h"
#include "numeric/ProjectedRank.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>

namespace ldae::passes {

namespace {

constexpr int kPoints = 3;    // random points per step (majority vote)
constexpr int kAttempts = 8;  // random starts per point before giving up
/// Floating-point operations the dense Jacobians and their minimum-norm
/// solves may cost in all (rows x cols x min(rows, cols) per Jacobian),
/// about a second here: a model whose prolongations stay far from their
/// points (a mutated chain that Gauss–Newton never settles) gets no formal
/// index rather than minutes of retries. Counted, not timed, so the answer
/// does not depend on the machine.
constexpr double kWorkBudget = 2e9;

/// The model as written: its continuous unknowns (numbered in declaration
/// order) and the order q of its jet space.
struct JetSpace {
  std::vector<ir::VarId> unknowns;
  std::vector<int> index; // VarId -> unknown, or -1
  int q = 1; // an algebraic model is a DAE of order 1 (docs/indices.md)

  explicit JetSpace(const ir::Model &model)
      : index(model.variables.size(), -1) {
    for (ir::VarId v = 0; v < model.variables.size(); ++v)
      if (!model.variables[v].isDiscrete) {
        index[v] = static_cast<int>(unknowns.size());
        unknowns.push_back(v);
      }
    for (const ir::Equation &eq : model.equations)
      for (ir::VarKey k : ir::freeVariables(eq.residual))
        if (k.var < index.size() && index[k.var] >= 0)
          q = std::max(q, static_cast<int>(k.order));
  }
};

/// The prolonged system: rows d^k Φ_i and their sparse Jacobians over the
/// jet coordinates, column k*m + j for unknown j at order k (so the
/// coordinates of order <= q come first).
class Prolongation {
public:
  Prolongation(const ir::Model &model, const JetSpace &jet)
      : model_(model), jet_(jet), diff_(model.ctx()), q_(jet.q),
        m_(static_cast<int>(jet.unknowns.size())),
        params_(model.parameterValues()) {
    for (const ir::Equation &eq : model.equations)
      addRow(eq.residual);
  }

  int unknowns() const { return m_; }
  int order() const { return q_; }
  /// Prolongations so far (s of R_{q+s}).
  int steps() const { return steps_; }
  int columns() const { return m_ * (q_ + steps_ + 1); }
  int lowColumns() const { return m_ * (q_ + 1); }
  Eigen::Index rows() const { return static_cast<Eigen::Index>(rows_.size()); }

  /// Adds d/dt of the rows of the last step.
  void prolong() {
    size_t first = rows_.size() - model_.equations.size();
    size_t last = rows_.size();
    for (size_t r = first; r < last; ++r)
      addRow(diff_.timeDerivative(rows_[r].expr));
    ++steps_;
  }

  bool residual(double t, const Eigen::VectorXd &x, Eigen::VectorXd &f) const {
    ir::EvalEnv env = envAt(t, x);
    f.resize(rows());
    for (Eigen::Index r = 0; r < rows(); ++r)
      if (!valueOf(rows_[r].expr, env, f(r)))
        return false;
    return true;
  }

  bool jacobian(double t, const Eigen::VectorXd &x, Eigen::MatrixXd &j) const {
    ir::EvalEnv env = envAt(t, x);
    j = Eigen::MatrixXd::Zero(rows(), columns());
    for (Eigen::Index r = 0; r < rows(); ++r)
      for (const auto &[col, partial] : rows_[r].partials)
        if (!valueOf(partial, env, j(r, col)))
          return false;
    return true;
  }

  /// A start for coordinate `col`: the unknown's start value at order 0,
  /// zero above, each spread by `noise` times its scale.
  double startValue(int col, double noise) const {
    const ir::Variable &v = model_.variables[jet_.unknowns[col % m_]];
    double scale = std::max({1.0, std::abs(v.start), std::abs(v.nominal)});
    return (col < m_ ? v.start : 0.0) + noise * scale;
  }

private:
  struct Row {
    ir::ExprRef expr;
    std::vector<std::pair<int, ir::ExprRef>> partials; // column, ∂row/∂col
  };
  const ir::Model &model_;
  const JetSpace &jet_;
  ir::Differentiator diff_;
  int q_, m_, steps_ = 0;
  std::vector<double> params_;
  std::vector<Row> rows_;

  int column(ir::VarKey k) const {
    if (k.var >= jet_.index.size() || jet_.index[k.var] < 0)
      return -1;
    return static_cast<int>(k.order) * m_ + jet_.index[k.var];
  }

  void addRow(ir::ExprRef e) {
    Row row{e, {}};
    for (ir::VarKey k : ir::freeVariables(e)) {
      int c = column(k);
      if (c >= 0)
        row.partials.emplace_back(c, diff_.partial(e, k));
    }
    rows_.push_back(std::move(row));
  }

  ir::EvalEnv envAt(double t, const Eigen::VectorXd &x) const {
    ir::EvalEnv env;
    env.time = t;
    env.variable = [this, &x](ir::VarKey k) {
      int c = column(k);
      if (c >= 0)
        return c < x.size() ? x[c] : 0.0;
      // Discrete variables keep their start value between events.
      if (k.order == 0 && k.var < model_.variables.size())
        return model_.variables[k.var].start;
      return 0.0;
    };
    env.parameter = [this](ir::ParamId p) {
      return p < params_.size() ? params_[p] : 0.0;
    };
    return env;
  }

  static bool valueOf(ir::ExprRef e, const ir::EvalEnv &env, double &out) {
    auto v = ir::evaluate(e, env);
    if (!v || !std::isfinite(*v))
      return false;
    out = *v;
    return true;
  }
};

struct Point {
  double t = 0;
  Eigen::VectorXd x;
};

class FormalIndex {
public:
  FormalIndex(const ir::Model &model, const JetSpace &jet)
      : sys_(model, jet), rng_(20261124),
        t0_(model.experiment.startTime.value_or(0.0)) {}

  FormalIndexResult run() {
    FormalIndexResult out;
    std::vector<Point> points(kPoints);
    std::optional<int> previous;
    // The dimension of J_q bounds the number of strict decreases.
    const int bound = sys_.lowColumns() + 1;
    for (int s = 0; s <= bound; ++s) {
      if (s > 0)
        sys_.prolong();
      std::optional<int> codim = codimension(points);
      if (work_ > kWorkBudget) {
        out.reason = "gave up after " + std::to_string(s) +
                     " prolongations: finding points on them costs more "
                     "than the work limit";
        out.dimensions.clear();
        return out;
      }
      if (!codim) {
        out.reason = "no point satisfies the equations prolonged " +
                     std::to_string(s) + " times";
        return out;
      }
      out.dimensions.push_back(sys_.lowColumns() - *codim);
      if (previous && *codim == *previous) {
        out.index = s - 1;
        return out;
      }
      previous = codim;
    }
    out.reason = "the projections did not become stationary";
    return out;
  }

private:
  Prolongation sys_;
  std::mt19937 rng_;
  double t0_;
  double work_ = 0; // operations spent (kWorkBudget)

  /// The Jacobian at (t, x), counting its solve's work; false once the
  /// budget is spent, which ends every iteration.
  bool jacobian(double t, const Eigen::VectorXd &x, Eigen::MatrixXd &j) {
    if (work_ > kWorkBudget || !sys_.jacobian(t, x, j))
      return false;
    work_ += double(j.rows()) * double(j.cols()) *
             double(std::min(j.rows(), j.cols()));
    return true;
  }

  /// The codimension of R_q^(s) most points agree on (the first point's on
  /// a tie); nullopt when no point of R_{q+s} can be found.
  std::optional<int> codimension(std::vector<Point> &points) {
    std::map<int, int> votes;
    std::optional<int> first;
    for (Point &p : points) {
      if (!place(p))
        return std::nullopt;
      Eigen::MatrixXd j;
      if (!jacobian(p.t, p.x, j))
        return std::nullopt;
      int c = numeric::projectedRank(j, sys_.lowColumns()).projected();
      ++votes[c];
      if (!first)
        first = c;
    }
    int best = *first;
    for (const auto &[c, n] : votes)
      if (n > votes[best])
        best = c;
    return best;
  }

  /// Gauss–Newton onto R_{q+s} at time t from x. Its minimum-norm steps
  /// favour the coordinates with the largest coefficients, and a
  /// capacitor's 1e-6 in front of a derivative lets them move voltages
  /// into exp() rather than the derivative: when the plain iteration
  /// fails, the derivatives (every coordinate of order >= 1) are fitted
  /// first with the order-0 values held, and all coordinates move only
  /// from there.
  bool solve(double t, Eigen::VectorXd &x) {
    numeric::ResidualFn f = [&](const Eigen::VectorXd &y, Eigen::VectorXd &r) {
      return sys_.residual(t, y, r);
    };
    numeric::JacobianFn jac = [&](const Eigen::VectorXd &y,
                                  Eigen::MatrixXd &j) {
      return jacobian(t, y, j);
    };
    numeric::NewtonOptions opts;
    opts.tolerance = 1e-11;
    Eigen::VectorXd plain = x;
    if (numeric::gaussNewton(f, jac, plain, opts).converged() &&
        regular(plain)) {
      x = std::move(plain);
      return true;
    }
    const Eigen::Index m = sys_.unknowns();
    Eigen::VectorXd held = x.head(m);
    auto full = [&](const Eigen::VectorXd &tail) {
      Eigen::VectorXd y(x.size());
      y << held, tail;
      return y;
    };
    numeric::ResidualFn fTail = [&](const Eigen::VectorXd &tail,
                                    Eigen::VectorXd &r) {
      return sys_.residual(t, full(tail), r);
    };
    numeric::JacobianFn jTail = [&](const Eigen::VectorXd &tail,
                                    Eigen::MatrixXd &j) {
      Eigen::MatrixXd all;
      if (!jacobian(t, full(tail), all))
        return false;
      j = all.rightCols(all.cols() - m);
      return true;
    };
    opts.maxIterations = 10;
    Eigen::VectorXd tail = x.tail(x.size() - m);
    if (numeric::gaussNewton(fTail, jTail, tail, opts).status !=
        numeric::NewtonStatus::EvaluationFailed)
      x = full(tail);
    opts.maxIterations = 50;
    return numeric::gaussNewton(f, jac, x, opts).converged() && regular(x);
  }

  /// Homogeneous equations (Vessiot's y3^2 = y1*y2 with linear ODEs) have
  /// a cone of solutions whose vertex, all coordinates 0, is where the
  /// minimum-norm steps lead from a start whose high derivatives are too
  /// large: a singular point, where the residual test (absolute below 1)
  /// says nothing about the ranks. Such a point is drawn again.
  static bool regular(const Eigen::VectorXd &x) {
    return x.size() == 0 || x.cwiseAbs().maxCoeff() > 1e-3;
  }

  /// Brings `p` onto R_{q+s}: from where it was (its new coordinates
  /// drawn at random), then from fresh random starts ever closer to the
  /// start values (a spread of half the scale overflows exp(v / 0.026)).
  bool place(Point &p) {
    std::normal_distribution<double> noise(0.0, 1.0);
    std::uniform_real_distribution<double> time(0.1, 0.9);
    const int n = sys_.columns();
    double spread = 0.5;
    for (int attempt = 0; attempt < kAttempts && work_ <= kWorkBudget;
         ++attempt, spread *= 0.25) {
      Eigen::Index kept = attempt == 0 ? std::min<Eigen::Index>(p.x.size(), n)
                                       : 0;
      if (kept == 0)
        p.t = t0_ + time(rng_);
      Eigen::VectorXd x(n);
      x.head(kept) = p.x.head(kept);
      for (int c = static_cast<int>(kept); c < n; ++c)
        x[c] = sys_.startValue(c, spread * noise(rng_));
      if (solve(p.t, x)) {
        p.x = std::move(x);
        return true;
      }
    }
    return false;
  }
};

class FormalIndexPass
    : public TypedPass<FormalIndexPass, Reads<>, Updates<>,
                       Produces<FormalIndexResult>> {
public:
  FormalIndexPass() : TypedPass(PassId::FormalIndex) {}

  bool runOn(PassContext &ctx, FormalIndexResult &out) {
    // A report only: a run or an emitted file does not pay for it (up to
    // 0.2 s of CPU, a third of a small model's whole run).
    if (!ctx.opts.reportOnly) {
      out.reason = "computed by --analyze only";
      ctx.report.formalIndexNote = out.reason;
      return true;
    }
    out = formalIndex(ctx.model);
    ctx.report.formalIndex = out.index;
    ctx.report.formalIndexNote = out.reason;
    ctx.report.formalDimensions = out.dimensions;
    return true; // a report, never a reason to stop
  }
};

} // namespace

FormalIndexResult formalIndex(const ir::Model &model, size_t maxCoordinates) {
  JetSpace jet(model);
  const size_t coordinates = jet.unknowns.size() * (jet.q + 1);
  FormalIndexResult out;
  if (jet.unknowns.empty() || model.equations.empty())
    out.reason = "no equations over unknowns";
  else if (coordinates > maxCoordinates)
    out.reason = std::to_string(coordinates) +
                 " jet coordinates, above the dense limit of " +
                 std::to_string(maxCoordinates);
  else
    out = FormalIndex(model, jet).run();
  return out;
}

std::unique_ptr<Pass> createFormalIndexPass() {
  return std::make_unique<FormalIndexPass>();
}

} // namespace ldae::passes
