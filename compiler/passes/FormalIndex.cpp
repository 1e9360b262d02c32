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
// (numeric/ProjectedRank.h). The points are the SGA's (ManifoldSampler.h):
// moves of an anchor reached from the start values at s = 0, then carried
// from step to step; each step takes the codimension most of kPoints points
// agree on. Nothing is decided from syntactic zeros. See docs/indices.md.
#include "passes/FormalIndex.h"
#include "passes/ManifoldSampler.h"
#include "passes/PassContext.h"
#include "passes/Passes.h"

#include "ir/Differentiate.h"
#include "ir/Query.h"
#include "numeric/ProjectedRank.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace ldae::passes {

namespace {

constexpr int kPoints = 3; // points per step (majority vote)
/// Floating-point operations the dense Jacobians and their minimum-norm
/// solves may cost in all (rows x moving cols x the smaller, per
/// Jacobian), under 2 s of CPU here; Andrews' squeezer, decided, spends
/// 1.5e9 (0.8 s). A model whose prolongations stay far from their
/// points (a mutated chain that Gauss–Newton never settles) gets no formal
/// index rather than minutes of retries. Counted, not timed, so the answer
/// does not depend on the machine.
constexpr double kWorkBudget = 3e9;

/// The model as written: its continuous unknowns (numbered in declaration
/// order) and the order q of its jet space.
struct JetSpace {
  std::vector<ir::VarId> unknowns;
  std::vector<int> index; // VarId -> unknown, or -1
  std::vector<int> top;   // per unknown: its highest order in the model
  int q = 1; // an algebraic model is a DAE of order 1 (docs/indices.md)

  explicit JetSpace(const ir::Model &model)
      : index(model.variables.size(), -1) {
    for (ir::VarId v = 0; v < model.variables.size(); ++v)
      if (!model.variables[v].isDiscrete) {
        index[v] = static_cast<int>(unknowns.size());
        unknowns.push_back(v);
      }
    top.assign(unknowns.size(), 0);
    for (const ir::Equation &eq : model.equations)
      for (ir::VarKey k : ir::freeVariables(eq.residual))
        if (k.var < index.size() && index[k.var] >= 0) {
          int &t = top[static_cast<size_t>(index[k.var])];
          t = std::max(t, static_cast<int>(k.order));
          q = std::max(q, t);
        }
  }
};

/// The prolonged system R_{q+s}: rows d^k Phi_i (k <= s) as the equations
/// of a ManifoldSampler over the jet coordinates, coordinate k*m + j for
/// unknown j at order k (so the coordinates of order <= q come first).
class Prolongation {
public:
  Prolongation(const ir::Model &model, const JetSpace &jet)
      : jet_(jet), diff_(model.ctx()), q_(jet.q),
        m_(static_cast<int>(jet.unknowns.size())),
        points_(model, diff_, coordinates(jet, 0, jet.q)) {
    std::vector<ir::ExprRef> defining;
    for (const ir::Equation &eq : model.equations) {
      points_.addEquation(eq.residual, 0);
      last_.push_back(eq.residual);
      // Below the top order: an equation that computes an unknown
      // without a start value from the others (`lang = sqrt(...)`).
      bool low = true;
      for (ir::VarKey k : ir::freeVariables(eq.residual))
        low = low && static_cast<int>(k.order) < q_;
      if (low)
        defining.push_back(eq.residual);
    }
    points_.findAssignments(defining);
  }

  int order() const { return q_; }
  int columns() const { return m_ * (q_ + steps_ + 1); }
  int lowColumns() const { return m_ * (q_ + 1); }
  ManifoldSampler &points() { return points_; }

  /// Adds d/dt of the rows of the last step, over the coordinates of the
  /// next order.
  void prolong() {
    ++steps_;
    points_.addCoordinates(coordinates(jet_, q_ + steps_, q_ + steps_));
    for (ir::ExprRef &row : last_) {
      row = diff_.timeDerivative(row);
      // One generation: the hidden equations a prolongation brings read
      // the coordinates of the steps before, which a projection a
      // generation at a time would hold.
      points_.addEquation(row, 0);
    }
  }

private:
  const JetSpace &jet_;
  ir::Differentiator diff_;
  int q_, m_, steps_ = 0;
  ManifoldSampler points_;
  std::vector<ir::ExprRef> last_; // the rows of the last step

  static std::vector<ir::VarKey> coordinates(const JetSpace &jet, int from,
                                             int to) {
    std::vector<ir::VarKey> keys;
    for (int k = from; k <= to; ++k)
      for (ir::VarId v : jet.unknowns)
        keys.push_back({v, static_cast<unsigned>(k)});
    return keys;
  }
};

class FormalIndex {
public:
  FormalIndex(const ir::Model &model, const JetSpace &jet)
      : jet_(jet), sys_(model, jet) {
    ManifoldSampler &points = sys_.points();
    points.workBudget = kWorkBudget;
    points.diagnoseFailures = false;
    points.acceptable = [](const SamplePoint &p) { return regular(p.x); };
  }

  FormalIndexResult run() {
    FormalIndexResult out;
    std::optional<int> previous;
    // The dimension of J_q bounds the number of strict decreases.
    const int bound = sys_.lowColumns() + 1;
    for (int s = 0; s <= bound; ++s) {
      if (s > 0)
        sys_.prolong();
      std::optional<int> codim = codimension();
      if (sys_.points().exhausted()) {
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
      // R_q^(s) lies in R_q^(s-1): a codimension below the last step's
      // is a rank lost to rounding in the larger Jacobian, not a set
      // that grew.
      if (previous)
        codim = std::max(*codim, *previous);
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
  const JetSpace &jet_;
  Prolongation sys_;
  std::vector<SamplePoint> points_; // on R_{q+s} for the last s

  /// The points of the last step onto R_{q+s}, each on its own (their
  /// coordinates stay generic: perturbations of one anchor move mostly
  /// the new, highest coordinates). As initialization solves a mechanism,
  /// from the most held to the least: the new coordinates alone; the
  /// coordinates above order q (all a step without a new equation of
  /// order <= q needs: it may fix a multiplier's second derivative, left
  /// free before); everything but the state, each unknown below its
  /// highest order in the model
  /// (a multiplier's equation moves the multiplier, not the positions
  /// and velocities it is read with, whose nonlinear terms made all-
  /// coordinate steps on Andrews' squeezer take 20 to 40 iterations);
  /// then all coordinates. Each try starts where the one before ended:
  /// a least-squares fit is a better start than 0 (Andrews' q'' = v',
  /// some 1e4 rad/s^2, stalled from 0).
  bool carry(std::vector<SamplePoint> &pts) {
    ManifoldSampler &points = sys_.points();
    if (pts.empty())
      return false;
    const size_t count = points.equations().size();
    const size_t n = points.coordinates().size();
    const Eigen::Index known = pts.front().x.size();
    std::vector<char> old(n, 0), low(n, 0), state(n, 0);
    std::fill(old.begin(), old.begin() + known, 1);
    for (size_t c = 0; c < n; ++c) {
      ir::VarKey k = points.coordinates()[c];
      low[c] = static_cast<int>(k.order) <= jet_.q;
      state[c] = static_cast<int>(k.order) <
                 jet_.top[static_cast<size_t>(jet_.index[k.var])];
    }
    for (SamplePoint &p : pts) {
      p.x.conservativeResize(static_cast<Eigen::Index>(n));
      p.x.tail(static_cast<Eigen::Index>(n) - known).setZero();
      bool on = false;
      for (const std::vector<char> *held : {&old, &low, &state}) {
        SamplePoint tried = p;
        on = points.project(tried, count, held) && points.definedAt(tried);
        if (tried.x.allFinite())
          p = std::move(tried);
        if (on)
          break;
      }
      if (!on && !(points.project(p, count) && points.definedAt(p)))
        return false;
    }
    return true;
  }

  /// The codimension of R_q^(s) most points agree on (the first point's on
  /// a tie); nullopt when no point of R_{q+s} can be found.
  std::optional<int> codimension() {
    ManifoldSampler &points = sys_.points();
    std::vector<SamplePoint> &pts = points_;
    if (!(carry(pts) || points.samplePoints(pts, kPoints)))
      return std::nullopt;
    // The start values may be special (a mechanism at rest: the terms
    // quadratic in the velocities vanish, and with them singular values
    // of the prolongations); a sample point is generic, and the anchor
    // from which the next steps start.
    points.setAnchorState({pts.front(), points.equations().size(), false});
    std::map<int, int> votes;
    std::optional<int> first;
    for (const SamplePoint &p : pts) {
      Eigen::MatrixXd j;
      if (!points.jacobianAt(p, points.equations().size(), j))
        return std::nullopt;
      auto pr = numeric::projectedRank(j, sys_.lowColumns());
      int c = pr.projected();
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

  /// Homogeneous equations (Vessiot's y3^2 = y1*y2 with linear ODEs) have
  /// a cone of solutions whose vertex, all coordinates 0, is a singular
  /// point, where the residual test (absolute below 1) says nothing about
  /// the ranks. Such a point is not a sample point.
  static bool regular(const Eigen::VectorXd &x) {
    return x.size() == 0 || x.cwiseAbs().maxCoeff() > 1e-3;
  }
};

/// Above this many equations --analyze does not run Pantelides on the
/// model as written a second time.
constexpr size_t kMaxEquationsAsWritten = 100000;

class FormalIndexPass : public TypedPass<FormalIndexPass, Reads<>, Updates<>,
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
    // The structural index of the model as written, beside the one of the
    // system after alias elimination (pass pantelides); bounded like the
    // formal index's work, as a report.
    if (ctx.model.equations.size() <= kMaxEquationsAsWritten)
      ctx.report.structuralIndexAsWritten =
          structuralIndexAsWritten(ctx.model);
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
  else if (std::string c = externalOfUnknowns(model); !c.empty())
    out.reason = "the model calls the external function '" + c +
                 "' at values of its unknowns, and C code is called only at "
                 "points a run reaches";
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
