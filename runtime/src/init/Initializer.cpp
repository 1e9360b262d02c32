// The initializer (Initializer.h): the choice among the paths of init/,
// the homotopy continuation, and the messages and log lines of each.
#include "init/Initializer.h"
#include "init/ConsistentInit.h"
#include "init/SparseInit.h"

#include <algorithm>
#include <fmt/format.h>
#include <ostream>

namespace ldae::runtime {

namespace {

/// Above this many unknowns the general initialization (dense Wong
/// sequences and least squares on n x 2n matrices, O(n^3)) would need hours
/// and gigabytes; it fails with a message instead.
constexpr int kMaxDenseInitUnknowns = 10000;

/// The relations (LDAE_DISCRETE_RELATION) re-evaluated at (t, y, y'),
/// the frozen values set to them; true when one changed. Along the
/// continuation a model's if-branches follow the point as in an event
/// iteration, so that the path is the actual model's and not that of the
/// branches the start values chose: a limiter whose simplified model is
/// its lower limit stays on it only if its `x < lower` is re-evaluated
/// there (the Schmitt trigger of MSL's OpAmps.SignalGenerator).
bool followRelations(ModelEval &ev, double t, const std::vector<double> &y,
                     const std::vector<double> &yp) {
  const ldae_model &m = ev.model();
  if (m.n_discrete == 0 || !m.event_update || !m.discrete_kind)
    return false;
  std::vector<double> out(m.n_discrete + 2 * std::max(m.n_reinit, 0) +
                          std::max(m.n_terminate, 0));
  if (m.event_update(t, y.data(), yp.data(), ev.params(), out.data()) != 0)
    return false;
  bool changed = false;
  for (int k = 0; k < m.n_discrete; ++k)
    if (m.discrete_kind[k] == LDAE_DISCRETE_RELATION &&
        out[k] != ev.discrete()[k]) {
      ev.discrete()[k] = ev.pre()[k] = out[k];
      changed = true;
    }
  return changed;
}

/// One initialization: the paths tried in order, the continuation around
/// them; `failure_` is the user's message of the last one that failed.
class Initializer {
public:
  Initializer(ModelEval &ev, InitTarget &target, int set, double t0,
              double tNext, std::ostream *log)
      : ev_(ev), target_(target), set_(set), t0_(t0), tNext_(tNext), log_(log) {
  }

  bool initialize(ContinuationKind continuation);

private:
  bool initializeFrom(std::vector<double> y, std::vector<double> yp,
                      std::ostream *log);
  bool adopt(const std::vector<double> &y0, const InitOutcome &init,
             std::ostream *log);
  bool restart(const std::vector<double> &y, const std::vector<double> &yp);
  std::string describe(const InitOutcome &init) const;
  bool homotopyContinuation(int lambda);

public:
  /// The user's message of the failure, once initialize returned false.
  std::string takeFailure() { return std::move(failure_); }

private:
  std::string failure_;
  ModelEval &ev_;
  InitTarget &target_;
  const int set_;
  const double t0_, tNext_;
  std::ostream *log_;
};

/// Restarts the target at (y, y'); false with the failure.
bool Initializer::restart(const std::vector<double> &y,
                          const std::vector<double> &yp) {
  if (auto failed = target_.restart(set_, t0_, y.data(), yp.data())) {
    failure_ = *failed;
    return false;
  }
  return true;
}

/// Hands a consistent point found by our own Newton iteration to the
/// target.
bool Initializer::adopt(const std::vector<double> &y0, const InitOutcome &init,
                        std::ostream *log) {
  reportMoves(ev_, y0, init.y.data(), log);
  return restart(init.y, init.yp);
}

/// The message of a failed initialization: a domain error in the same form
/// as one during the run, else the outcome's own text.
std::string Initializer::describe(const InitOutcome &init) const {
  if (init.domainRow >= 0)
    return target_.describeDomainError(set_, init.domainRow,
                                       init.domainY.data(), t0_);
  return fmt::format("initialization failed at t = {}: {}", t0_, init.failure);
}

/// Finds the initial point from the start vector (y, yp) (the target holds
/// it); false (with the failure) when there is none.
bool Initializer::initializeFrom(std::vector<double> y, std::vector<double> yp,
                                 std::ostream *log) {
  const int n = ev_.n();
  if (isPlainIndexOne(ev_, set_, t0_, y.data(), yp.data())) {
    if (target_.completeStart(tNext_)) {
      if (log)
        *log << "initialization: index-1 structure; algebraic values and "
                "derivatives solved from the differential start values\n";
      reportMoves(ev_, y, target_.y(), log);
      return true;
    }
    if (usesSparseInit(ev_)) {
      // The same rule by our own Newton iteration (tighter tolerance, no
      // dependence on the first output time), still sparse.
      InitOutcome init = initializeIndexOne(ev_, set_, t0_, y, yp);
      if (!init.ok && init.domainRow >= 0) {
        failure_ = describe(init);
        return false;
      }
      if (init.ok) {
        if (log)
          *log << "initialization: IDACalcIC failed; index-1 Newton "
                  "iteration (sparse) solved the algebraic values and "
                  "derivatives\n";
        return adopt(y, init, log);
      }
    }
    if (log)
      *log << "initialization: IDACalcIC failed; trying Newton steps along "
              "the jump space\n";
    if (!restart(y, yp))
      return false;
  }
  if (usesSparseInit(ev_)) {
    InitOutcome init = initializeSparse(ev_, set_, t0_, y, yp);
    if (init.ok) {
      if (log)
        *log << fmt::format(
            "initialization: sparse Newton iteration (KLU) on the residuals, "
            "fixed values and initial equations; {} differential values "
            "kept, {} moved by the conditions{}\n",
            init.kept, init.moved,
            init.projected
                ? fmt::format(" ({} in minimum-norm blocks)", init.projected)
                : std::string());
      return adopt(y, init, log);
    }
    if (init.applicable) {
      failure_ = describe(init);
      return false;
    }
    if (log)
      *log << "initialization: the sparse path does not apply (" +
                  init.failure + "); using the dense one\n";
    if (n > kMaxDenseInitUnknowns) {
      failure_ = fmt::format(
          "initialization failed at t = {}: {}; and the general "
          "initialization along the jump space is dense: {} unknowns are "
          "more than it handles ({})",
          t0_, init.failure, n, kMaxDenseInitUnknowns);
      return false;
    }
  }
  if (n > kMaxDenseInitUnknowns) {
    failure_ = fmt::format(
        "initialization failed at t = {}: the model is not plain index-1 at "
        "the start values (or has initial equations or fixed algebraic "
        "values), and the general initialization along the jump space is "
        "dense: {} unknowns are more than it handles ({})",
        t0_, n, kMaxDenseInitUnknowns);
    return false;
  }
  InitOutcome init = initializeAlongJumps(ev_, set_, t0_, y, yp, log);
  if (!init.ok) {
    failure_ = describe(init);
    return false;
  }
  if (log)
    *log << fmt::format("initialization: start values moved along the jump "
                        "space T (dimension {}, index {}){}\n",
                        init.jumpDim, init.index,
                        init.nearestPoint ? "; nearest point used" : "");
  return adopt(y, init, log);
}

/// The continuation of homotopy(): from the simplified model (lambda = 0),
/// solved from the start values, to the actual one (lambda = 1), each
/// initialization starting from the last; the step in lambda grows after a
/// success and halves after a failure. At each point the relations follow
/// the solution (followRelations) until they settle.
bool Initializer::homotopyContinuation(int lambda) {
  const ldae_model &m = ev_.model();
  const int n = ev_.n();
  std::vector<double> y(m.start_y, m.start_y + n),
      yp(m.start_yp, m.start_yp + n);
  // Initializes at lambda = l from (y, y'), again from each solution while
  // the relations it reaches differ from those it was solved with.
  constexpr int kMaxRelationRounds = 20;
  // Discrete values and pre() values: a failed step goes back to those of
  // the last point reached.
  const int nd2 = 2 * m.n_discrete;
  std::vector<double> discrete(ev_.discrete(), ev_.discrete() + nd2);
  auto from = [&](double l) {
    ev_.setParam(lambda, l);
    std::copy(discrete.begin(), discrete.end(), ev_.discrete());
    std::vector<double> y0 = y, yp0 = yp;
    for (int round = 0; round < kMaxRelationRounds; ++round) {
      failure_.clear();
      // A failed restart leaves the failure empty, as it always has.
      if (target_.restart(set_, t0_, y0.data(), yp0.data()) ||
          !initializeFrom(y0, yp0, nullptr))
        return false;
      y0.assign(target_.y(), target_.y() + n);
      yp0.assign(target_.yp(), target_.yp() + n);
      if (!followRelations(ev_, t0_, y0, yp0))
        return true;
    }
    return true;
  };
  const std::vector<double> discreteAtStart = discrete;
  auto giveUp = [&] {
    ev_.setParam(lambda, 1.0);
    std::copy(discreteAtStart.begin(), discreteAtStart.end(), ev_.discrete());
  };
  if (!from(0.0)) {
    giveUp();
    failure_ = "the simplified model of homotopy() (lambda = 0) does not "
               "initialize either: " +
               failure_;
    return false;
  }
  // The last point reached, where a failed step goes back to.
  auto reached = [&] {
    y.assign(target_.y(), target_.y() + n);
    yp.assign(target_.yp(), target_.yp() + n);
    discrete.assign(ev_.discrete(), ev_.discrete() + nd2);
  };
  reached();
  double l = 0, step = 0.1;
  int steps = 0;
  while (l < 1) {
    double next = std::min(1.0, l + step);
    if (from(next)) {
      reached();
      l = next;
      ++steps;
      step *= 1.5;
      continue;
    }
    step /= 2;
    if (step < 1e-6) {
      giveUp();
      failure_ = fmt::format("the homotopy continuation stalled at lambda "
                             "= {:.6g}: ",
                             l) +
                 failure_;
      return false;
    }
  }
  if (log_)
    *log_ << fmt::format("initialization: homotopy continuation from the "
                         "simplified model to the actual one in {} steps\n",
                         steps);
  return true;
}

bool Initializer::initialize(ContinuationKind continuation) {
  const ldae_model &m = ev_.model();
  const int n = ev_.n();
  std::vector<double> y(m.start_y, m.start_y + n),
      yp(m.start_yp, m.start_yp + n);
  int lambda = ev_.paramIndex(LDAE_HOMOTOPY_LAMBDA);
  if (continuation == ContinuationKind::None || lambda < 0 ||
      ev_.params()[lambda] != 1.0)
    return initializeFrom(y, yp, log_);
  if (homotopyContinuation(lambda))
    return true;
  std::string continued = failure_;
  if (log_)
    *log_ << "initialization: the homotopy continuation failed; trying the "
             "actual model from the start values\n";
  failure_.clear();
  if (!restart(y, yp))
    return false;
  if (initializeFrom(y, yp, log_))
    return true;
  failure_ += "\n  homotopy continuation: " + continued;
  return false;
}

} // namespace

InitOutcome initialize(ModelEval &ev, InitTarget &target, int set, double t0,
                       double tNext, ContinuationKind continuation,
                       std::ostream *log) {
  Initializer initializer(ev, target, set, t0, tNext, log);
  InitOutcome outcome;
  outcome.ok = initializer.initialize(continuation);
  if (!outcome.ok) {
    outcome.failure = initializer.takeFailure();
    return outcome;
  }
  const int n = ev.n();
  outcome.y.assign(target.y(), target.y() + n);
  outcome.yp.assign(target.yp(), target.yp() + n);
  return outcome;
}

} // namespace ldae::runtime
