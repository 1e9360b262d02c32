// The simulation driver (see ldae/Simulation.h): resolve options, find a
// consistent initial point, step the integrator (IDA or CVODE, behind
// Integrator.h) one internal step at a time, interpolate onto the output
// grid, switch state sets when the current one's pivot degrades, and keep
// the results of a failed run.
#include "events/Asserts.h"
#include "results/Columns.h"
#include "init/ConsistentInit.h"
#include "init/Initializer.h"
#include "events/EventLoop.h"
#include "run/FailureReport.h"
#include "integrators/Integrator.h"
#include "run/Progress.h"
#include "ldae/Rebind.h"
#include "results/RowLog.h"
#include "ldae/ResultWriter.h"
#include "events/RootWatch.h"
#include "events/RoundOffZeros.h"
#include "model/StateSelection.h"
#include "events/TimeRoots.h"
#include "ldae/Simulation.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <limits>
#include <fmt/format.h>
#include <map>
#include <ostream>

namespace ldae::runtime {

namespace {

double pick(const std::optional<double> &opt, double fromModel, double dflt) {
  if (opt)
    return *opt;
  return std::isnan(fromModel) ? dflt : fromModel;
}

/// Resolved settings of one run.
struct RunSettings {
  double start, stop, rtol, atol, interval;
};

Expected<RunSettings> resolve(const ldae_model &m, const SimOptions &o) {
  RunSettings s;
  s.start = pick(o.start, m.start_time, 0.0);
  // Explicit output times end the run at the last one unless a stop is
  // given: they come before the model's experiment annotation.
  std::optional<double> stop = o.stop;
  if (!stop && !o.times.empty())
    stop = o.times.back();
  s.stop = pick(stop, m.stop_time, 1.0);
  s.rtol = pick(o.rtol, m.tolerance, 1e-6);
  s.atol = o.atol ? *o.atol : s.rtol;
  s.interval = pick(o.interval, m.interval, (s.stop - s.start) / 500);
  // Non-finite times or tolerances make every later computation NaN (or
  // an endless run); the driver rejects them on its command line already,
  // this catches the experiment annotation and other callers.
  for (auto [what, v] : {std::pair{"start time", s.start},
                         {"stop time", s.stop},
                         {"rtol", s.rtol},
                         {"atol", s.atol}})
    if (!std::isfinite(v))
      return Error{fmt::format("the {} {} is not finite", what, v)};
  if (o.interval && !std::isfinite(*o.interval))
    return Error{
        fmt::format("the output interval {} is not finite", *o.interval)};
  if (!(s.stop >= s.start))
    return Error{fmt::format("the stop time {} is before the start time {}",
                             s.stop, s.start)};
  if (!(s.rtol > 0) || !(s.atol > 0))
    return Error{"tolerances must be positive"};
  if (!(s.interval > 0) && s.stop > s.start)
    return Error{"the output interval must be positive"};
  if (s.stop > s.start && o.times.empty() && !o.everyStep &&
      outputRows(s.start, s.stop, s.interval) > kMaxOutputRows)
    return Error{tooManyRowsMessage(s.start, s.stop, s.interval)};
  for (size_t i = 0; i < o.times.size(); ++i)
    if (!(o.times[i] > s.start && o.times[i] <= s.stop) ||
        (i > 0 && !(o.times[i] > o.times[i - 1])))
      return Error{"output times must increase within (start, stop]"};
  return s;
}

/// The parameters of a mode's model: the run's, bound again (Rebind.h).
Expected<std::vector<double>> modeParams(const ldae_model &m,
                                         const SimOptions &o, double t) {
  auto bound = bindValues(m, o.params, {}, t);
  if (!bound)
    return Error{bound.error()};
  if (!bound->failure.empty())
    return Error{bound->failure};
  return std::move(bound->p);
}

/// Collects rows and the drift maximum.
class Recorder {
public:
  Recorder(const ModelEval &ev, std::vector<int> cols, RowLog &rows,
           SimResult &res, AssertChecker *asserts)
      : ev_(ev), m_(ev.model()), cols_(std::move(cols)), rows_(rows),
        res_(res), asserts_(asserts), out_(std::max(m_.n_outputs, 0)),
        drift_(std::max(m_.n_drift, 0)) {}

  /// Appends the row at `t`; false (and the failure) when an output left
  /// its domain there or an assert of level error does not hold: the rows
  /// so far are kept, the run stops.
  bool record(double t, const double *y, const double *yp) {
    std::vector<double> row;
    row.reserve(cols_.size() + 1); // one allocation, no slack per row
    row.push_back(t);
    const double *src = y;
    if (m_.n_outputs > 0) {
      int rc = m_.outputs(t, y, yp, ev_.params(), out_.data());
      if (rc != 0) {
        double lastGood = rows_.empty() ? t : rows_.lastTime();
        res_.failure =
            rc > 0 ? describeOutputDomainError(ev_, rc - 1, t, lastGood, y)
                   : fmt::format("simulation failed at t = {:.10g}: the "
                                 "outputs could not be computed",
                                 t);
        return false;
      }
      src = out_.data();
    }
    const int sources = m_.n_outputs > 0 ? m_.n_outputs : m_.n;
    for (int c : cols_)
      row.push_back(columnValue(c, sources, src, ev_.params()));
    if (!rows_.push(std::move(row)))
      return false; // the result file refused it (SimResult::writeFailure)
    if (m_.n_drift > 0 && m_.drift &&
        m_.drift(t, y, yp, ev_.params(), drift_.data()) == 0)
      for (double d : drift_)
        res_.stats.maxDrift = std::max(res_.stats.maxDrift, std::fabs(d));
    if (asserts_)
      if (auto failed = asserts_->check(t, y, yp)) {
        res_.failure = *failed;
        return false;
      }
    return true;
  }

private:
  const ModelEval &ev_;
  const ldae_model &m_;
  std::vector<int> cols_;
  RowLog &rows_;
  SimResult &res_;
  AssertChecker *asserts_;
  std::vector<double> out_, drift_;
};

/// The failure of a run whose state slides along root j's surface since
/// `since` (RootWatch::sliding).
std::string slidingMessage(const ModelEval &ev, int j, double t,
                           double since) {
  const ldae_model &m = ev.model();
  std::string relation =
      m.root_relation ? "'" + ev.discreteName(m.root_relation[j]) + "'"
                      : fmt::format("root function {}", j + 1);
  return fmt::format(
      "sliding at t = {:.10g}: the condition {} changed {} times since t = "
      "{:.10g} (every {:.3g} s), its two sides never apart by more than "
      "{:g} of their largest difference in the run in between: the state "
      "chatters along the surface where they are equal (a sliding mode, as "
      "of an ideal relay in a feedback loop), which ldaec does not "
      "integrate\n"
      "  hint: the solution is the average of both sides' dynamics that "
      "keeps it on the surface (Filippov); model that mode, or a hysteresis "
      "or a smooth characteristic",
      t, relation, kChatterEvents, since,
      (t - since) / double(kChatterEvents), 1e-3);
}

/// The most mode switches at one time (one event iteration across the
/// modes' models; EventLoop allows 100 updates within one model).
constexpr int kMaxModeSwitchesAtOnce = 100;

/// The most steps between two output times (of the interval grid, also
/// with --every-step or explicit times): a solution that blows up or
/// oscillates ever faster would otherwise step for ever (the solvers'
/// own limit, mxstep, counts steps per solver call, and each of our calls
/// is one step). SUNDIALS' own default is 500 per output.
constexpr long kMaxStepsPerOutput = 100000;

/// The most jumps past a fold between two output times: each restarts the
/// step count, so a relaxation oscillation far faster than the output
/// interval (a fuzzer's op-amp multivibrator with R multiplied instead of
/// divided, a period of 5e-8 s) would otherwise jump for ever.
constexpr long kMaxFoldJumpsPerOutput = 1000;

/// The initializer's target (Initializer.h): the integrator, its failures
/// in the run's report.
class IntegratorInitTarget : public InitTarget {
public:
  IntegratorInitTarget(const ModelEval &ev, Integrator &integrator)
      : ev_(ev), integrator_(integrator) {}

  std::optional<std::string> restart(int set, double t, const double *y,
                                     const double *yp) override {
    auto re = integrator_.reinit(set, t, y, yp);
    if (!re)
      return describeSolverError(t, re.error());
    return std::nullopt;
  }
  bool completeStart(double tNext) override {
    return integrator_.completeStart(tNext).ok();
  }
  const double *y() const override { return integrator_.y(); }
  const double *yp() const override { return integrator_.yp(); }
  std::string describeDomainError(int set, int row, const double *y,
                                  double t) const override {
    return describeInitDomainError(ev_, set, row, y, t);
  }

private:
  const ModelEval &ev_;
  Integrator &integrator_;
};

/// The re-initialization after an event by the jump rule (the state just
/// before, reinit values written in, onto the consistent set of the current
/// discrete values along T of the model as written, the reinit targets
/// `held`), and the integrator restarted there. False with `failure`.
bool restartAfterEvent(const ModelEval &ev, Integrator &integrator, double t,
                       std::vector<double> &y, std::vector<double> &yp,
                       const std::vector<int> &held, std::string &failure,
                       std::ostream *log) {
  // The moves are logged as the event's jump (EventLoop), not twice.
  integrator.nextReinitAfterEvent(held);
  InitOutcome init =
      reinitializeAfterEvent(ev, integrator.set(), t, y, yp, held, nullptr);
  if (!init.ok) {
    failure =
        init.domainRow >= 0
            ? describeEventDomainError(ev, integrator.set(), init.domainRow,
                                       init.domainY.data(), t)
            : fmt::format("the re-initialization after the event at t "
                          "= {:.10g} failed: {}",
                          t, init.failure);
    return false;
  }
  if (init.nearestPoint && log)
    *log << fmt::format("t = {:.10g}: re-initialization: holding the reinit "
                        "values leaves no step along the jump space; the "
                        "nearest consistent point is used\n",
                        t);
  // The relations of the event iteration read this point.
  snapRoundOffZeros(ev, init.y, init.yp, y.data(), yp.data());
  auto re =
      integrator.reinit(integrator.set(), t, init.y.data(), init.yp.data());
  if (!re) {
    failure = describeSolverError(t, re.error());
    return false;
  }
  // The integrator's point: a projecting one (sga) moved it onto its
  // constraints after the rows were solved.
  const int n = ev.n();
  y.assign(integrator.y(), integrator.y() + n);
  yp.assign(integrator.yp(), integrator.yp() + n);
  return true;
}

/// Restarts the integrator at the current point with state set `to`.
/// Restarts the integrator at (t, y, y') with state set `set` after a
/// switch of states.
bool restartWith(const ModelEval &ev, Integrator &integrator, int set, double t,
                 double tNext, std::vector<double> &y, std::vector<double> &yp,
                 SimResult &res) {
  auto re = integrator.reinit(set, t, y.data(), yp.data());
  if (!re) {
    res.failure = describeSolverError(t, re.error());
    return false;
  }
  StepStatus started = integrator.completeStart(tNext);
  if (!started.ok()) {
    res.failure = describeInitFailure(ev, integrator, started, t) +
                  " (after switching states)";
    return false;
  }
  return true;
}

bool switchStates(const ModelEval &ev, Integrator &integrator, int to, double t,
                  double tNext, const std::vector<double> &cond, SimResult &res,
                  std::ostream *log) {
  int from = integrator.set();
  int n = ev.n();
  std::vector<double> y(integrator.y(), integrator.y() + n),
      yp(integrator.yp(), integrator.yp() + n);
  if (!restartWith(ev, integrator, to, t, tNext, y, yp, res))
    return false;
  ++res.stats.stateSwitches;
  if (log) {
    auto desc = [&](int k) {
      const char *d = ev.set(k).description;
      return d ? std::string(d) : fmt::format("set {}", k);
    };
    *log << fmt::format("t = {:.10g}: state selection switched from '{}' to "
                        "'{}' (pivot condition {:.3g} -> {:.3g})\n",
                        t, desc(from), desc(to), cond[from], cond[to]);
  }
  return true;
}

/// Dynamic state selection of the large blocks (StateSelection.h): where a
/// block's states switch, the integrator restarts from the same point with
/// the new selection.
bool reselectStates(ModelEval &ev, Integrator &integrator, double t,
                    double tNext, SimResult &res, std::ostream *log) {
  int n = ev.n();
  std::vector<double> y(integrator.y(), integrator.y() + n),
      yp(integrator.yp(), integrator.yp() + n);
  std::vector<DynamicSwitch> sw =
      reselectDynamicSets(ev, t, y.data(), yp.data());
  if (sw.empty())
    return true;
  if (!restartWith(ev, integrator, integrator.set(), t, tNext, y, yp, res))
    return false;
  res.stats.stateSwitches += static_cast<int>(sw.size());
  for (const DynamicSwitch &d : sw)
    if (log)
      *log << fmt::format("t = {:.10g}: state selection switched from '{}' to "
                          "'{}' (pivot condition {:.3g} -> {:.3g})\n",
                          t, d.from, d.to, d.condFrom, d.condTo);
  return true;
}

/// The point a mode change hands from one mode's model to the next, by
/// name (every variable is an unknown or an output of each model).
struct Carry {
  bool valid = false; ///< false: the run starts from the start values
  double t = 0;
  std::map<std::string, double> y, yp, discrete;
  std::vector<double> modeValues; ///< of the new mode
  std::string mode;               ///< "'closed' = 1" for messages
};

/// A root the integrator returns can sit exactly on the crossing (g = 0:
/// a linear solution hits 0.8 to the last bit), where the relation still
/// reads its old value and the event would change nothing. Moves the event
/// point (t, y, y') within the last step to the first time, doubling from
/// a few ulps, at which every root found has the sign it crosses to.
void pastTheRoots(const ModelEval &ev, Integrator &integrator, double &t,
                  std::vector<double> &y, std::vector<double> &yp) {
  const ldae_model &m = ev.model();
  std::vector<int> found = integrator.rootsFound();
  std::vector<double> g(m.n_roots);
  auto crossed = [&](double at, const double *ya, const double *ypa) {
    if (m.roots(at, ya, ypa, ev.params(), g.data()) != 0)
      return true; // nothing better to be had
    for (int r = 0; r < m.n_roots; ++r)
      if (found[r] != 0 && !(g[r] * found[r] > 0))
        return false;
    return true;
  };
  // A variable-structure model carries this point into the next mode,
  // where its relations are read afresh: its algebraic values must be
  // their equations', not their interpolants (settleAlgebraic).
  const bool settle = m.n_mode > 0;
  if (settle)
    settleAlgebraic(ev, integrator.set(), t, y, yp);
  if (crossed(t, y.data(), yp.data()))
    return;
  double reach = integrator.currentTime();
  std::vector<double> ya(y.size()), ypa(yp.size());
  for (double d = 4e-16 * std::max(1.0, std::fabs(t)); t + d <= reach; d *= 2) {
    if (!integrator.interpolate(t + d, ya.data(), ypa.data()))
      return;
    if (settle)
      settleAlgebraic(ev, integrator.set(), t + d, ya, ypa);
    if (crossed(t + d, ya.data(), ypa.data())) {
      t += d;
      y = ya;
      yp = ypa;
      return;
    }
  }
}

/// How the run of one mode's model ended.
enum class StageEnd { Done, ModeChange };

/// One call of simulate(): the output grid, the table and the stages (a
/// variable-structure model runs one per mode it reaches).
class Run {
public:
  Run(const SimOptions &o, const RunSettings &s, SimResult &res, RowLog &rows)
      : o_(o), s_(s), res_(res), rows_(rows),
        progress_(o.progress, s.start, s.stop) {
    double span = s.stop - s.start;
    // Output grid start + k * interval, the last point exactly stop.
    nOut_ = !o.times.empty() ? long(o.times.size())
            : span > 0       ? long(outputRows(s.start, s.stop, s.interval)) - 1
                             : 0;
  }

  /// Whether SimOptions::interrupted asks the run to end at t (it then
  /// says so in the result).
  bool interrupted(double t) {
    if (!o_.interrupted || !o_.interrupted())
      return false;
    res_.interrupted = true;
    res_.failure = fmt::format("interrupted at t = {:.10g}", t);
    return true;
  }
  /// A model without unknowns: the outputs at the output times.
  void closedForm(const ldae_model &m, const std::vector<double> &params,
                  const std::vector<int> &cols);
  bool atStopTime(double t) const;
  /// Runs `m` from its start values (carry not valid) or from the carried
  /// point of a mode change, which it fills in when its own run ends in
  /// one. An Error only for options the model refuses.
  Expected<StageEnd> stage(const ldae_model &m,
                           const std::vector<double> &params,
                           const std::vector<int> &cols, Carry &carry);

private:
  double gridTime(long k) const {
    if (!o_.times.empty())
      return o_.times[k - 1];
    return k >= nOut_ ? s_.stop : s_.start + double(k) * s_.interval;
  }
  void carryOver(const ModelEval &ev, double t, const std::vector<double> &y,
                 const std::vector<double> &yp, Carry &carry) const;
  void startFrom(ModelEval &ev, const Carry &carry, std::vector<double> &y,
                 std::vector<double> &yp) const;

  const SimOptions &o_;
  const RunSettings &s_;
  SimResult &res_;
  RowLog &rows_;
  Progress progress_;
  long nOut_ = 0;
  long k_ = 1; // next output time (of the grid, also with --every-step)
};

void Run::closedForm(const ldae_model &m, const std::vector<double> &params,
                     const std::vector<int> &cols) {
  // Nothing left to integrate (alias elimination and constant folding
  // solved everything, or the model is discrete only): every output is a
  // function of time and the discrete values. SUNDIALS cannot take an
  // empty system (N_VMin of a length-0 vector reads element 0), so the run
  // walks the output times and the events itself. Without solver steps,
  // --every-step reports the same grid.
  ModelEval ev(m, params);
  AssertChecker asserts(ev, o_.log);
  Recorder rec(ev, cols, rows_, res_, &asserts);
  EventLoop events(ev, s_.rtol, o_.log);
  std::vector<double> y, yp; // length 0, never read
  const double *none = y.data();
  Reinitialize nothingToMove = [](double, std::vector<double> &,
                                  std::vector<double> &,
                                  const std::vector<int> &,
                                  std::string &) { return true; };
  double t = s_.start;
  struct Counted { // the events counted however the walk ends
    SimResult &res;
    const EventLoop &events;
    ~Counted() {
      res.stats.events += events.events();
      res.stats.timeEvents += events.timeEvents();
    }
  } counted{res_, events};
  // The rows an event outcome ends the run with; false to go on.
  auto ended = [&](EventOutcome out) {
    if (out == EventOutcome::Failed) {
      res_.failure = events.message();
      return true;
    }
    if (out != EventOutcome::Terminated)
      return false;
    if (o_.log)
      *o_.log << fmt::format("t = {:.10g}: terminate: {}; the run ends here\n",
                             t, events.message());
    if (rec.record(t, none, none) && events.terminal(t, none, none))
      rec.record(t, none, none);
    return true;
  };
  events.prime(t, none, none);
  if (ended(events.initial(t, y, yp, nothingToMove)) ||
      !rec.record(t, none, none) || !(s_.stop > s_.start))
    return;
  if (events.sampleInstantAt(t, none, none)) { // as in stage()
    EventOutcome out = events.handle(t, y, yp, true, nothingToMove);
    if (out != EventOutcome::Unchanged && out != EventOutcome::Restarted &&
        (ended(out) || !rec.record(t, none, none)))
      return;
  }
  TimeRoots crossing(ev);
  while (t < s_.stop) {
    if (interrupted(t))
      return;
    double target = k_ <= nOut_ ? gridTime(k_) : s_.stop;
    double timeEvent = events.nextTimeEvent(t, none, none);
    target = std::min(target, timeEvent);
    double root = events.handlesRoots() ? crossing.first(t, target) : target;
    bool rootEvent = root < target;
    if (rootEvent)
      target = root;
    t = target;
    bool recorded = true;
    for (; recorded && k_ <= nOut_ && gridTime(k_) <= t; ++k_)
      recorded = rec.record(gridTime(k_), none, none);
    if (!recorded)
      return;
    if (!rootEvent && t < timeEvent)
      continue;
    size_t rows = rows_.size();
    if (rows_.lastTime() != t && !rec.record(t, none, none))
      return;
    EventOutcome out = events.handle(t, y, yp, !rootEvent, nothingToMove);
    if (out == EventOutcome::Unchanged || out == EventOutcome::Restarted)
      rows_.truncate(rows);
    else if (ended(out))
      return;
    else if (!rec.record(t, none, none))
      return;
  }
  if (events.terminal(t, none, none))
    rec.record(t, none, none);
}

void Run::carryOver(const ModelEval &ev, double t, const std::vector<double> &y,
                    const std::vector<double> &yp, Carry &carry) const {
  const ldae_model &m = ev.model();
  carry = Carry{};
  carry.valid = true;
  carry.t = t;
  if (m.n_outputs > 0 && m.outputs) {
    std::vector<double> out(m.n_outputs);
    if (m.outputs(t, y.data(), yp.data(), ev.params(), out.data()) == 0)
      for (int i = 0; i < m.n_outputs; ++i)
        if (m.output_names && m.output_names[i])
          carry.y[m.output_names[i]] = out[i];
  }
  for (int i = 0; i < m.n; ++i) {
    carry.y[ev.varName(i)] = y[i];
    carry.yp[ev.varName(i)] = yp[i];
  }
  // A sample's instant is over with this event: the loop sets samples back
  // only when the mode stays (EventLoop::handle), and a sample carried as
  // true would make its next instant no rising edge (a when-clause on
  // sample(1, 1) that changed the mode at t = 1 missed t = 2).
  for (int k = 0; k < ev.nDiscrete(); ++k)
    carry.discrete[ev.discreteName(k)] =
        m.discrete_kind && m.discrete_kind[k] == LDAE_DISCRETE_SAMPLE
            ? 0.0
            : ev.discrete()[k];
  for (int i = 0; i < m.n_mode; ++i) {
    double v = ev.discrete()[m.mode_discrete[i]];
    carry.modeValues.push_back(v);
    carry.mode += fmt::format("{}'{}' = {:g}", i ? ", " : "",
                              ev.discreteName(m.mode_discrete[i]), v);
  }
}

void Run::startFrom(ModelEval &ev, const Carry &carry, std::vector<double> &y,
                    std::vector<double> &yp) const {
  for (int i = 0; i < ev.n(); ++i) {
    std::string name = ev.varName(i);
    if (auto it = carry.y.find(name); it != carry.y.end())
      y[i] = it->second;
    auto d = carry.yp.find(name);
    yp[i] = d != carry.yp.end() ? d->second : 0.0;
  }
  for (int k = 0; k < ev.nDiscrete(); ++k)
    if (auto it = carry.discrete.find(ev.discreteName(k));
        it != carry.discrete.end())
      ev.discrete()[k] = ev.pre()[k] = it->second;
}

/// Whether t is the stop time up to round-off: a sample's instant
/// computed as start + k * interval (0.02 + 9 * 0.02 = 0.19999999999999998
/// for a stop time 0.2) leaves no interval to integrate (IDA refuses a
/// tout that close), and the point there is the stop time's.
bool Run::atStopTime(double t) const {
  return t < s_.stop &&
         s_.stop - t <= 8 * std::numeric_limits<double>::epsilon() *
                            std::max(1.0, std::fabs(s_.stop));
}

Expected<StageEnd> Run::stage(const ldae_model &m,
                              const std::vector<double> &params,
                              const std::vector<int> &cols, Carry &carry) {
  const bool fromStart = !carry.valid;
  ModelEval ev(m, params);
  AssertChecker asserts(ev, o_.log);
  Recorder rec(ev, cols, rows_, res_, &asserts);
  EventLoop events(ev, s_.rtol, o_.log);
  RootWatch watch(ev);
  const int n = m.n;
  const double span = s_.stop - s_.start;
  double t = fromStart ? s_.start : carry.t;
  std::vector<double> y(m.start_y, m.start_y + n),
      yp(m.start_yp, m.start_yp + n);
  if (!fromStart)
    startFrom(ev, carry, y, yp);
  else
    events.prime(t, y.data(), yp.data());

  // Start with the best-conditioned state set at the start point.
  int set = chooseStateSet(pivotConditions(ev, t, y.data(), yp.data()), 0);
  reselectDynamicSets(ev, t, y.data(), yp.data());
  ErrorWeights weights(ev, s_.rtol, s_.atol);
  const bool errorTestAlgebraic =
      o_.algebraicErrorTest.value_or(m.algebraic_error_test != 0);
  auto firstOutput = [&](double from) {
    return span > 0 ? std::min(s_.stop, from + s_.interval) : from + 1e-6;
  };
  const bool weighsComputed = errorTestAlgebraic && weights.propagates();
  auto made = makeIntegrator(ev, o_.integrator, weighsComputed);
  if (!made) {
    if (fromStart)
      return Error{made.error()};
    res_.failure = fmt::format("t = {:.10g}: the model of the new mode: {}", t,
                               made.error());
    return StageEnd::Done;
  }
  Integrator &integrator = **made;
  auto done = [&](StageEnd end) -> Expected<StageEnd> {
    integrator.addCounters(res_.stats);
    res_.stats.sparse = integrator.sparse();
    res_.stats.integrator = integrator.name();
    res_.stats.events += events.events();
    res_.stats.timeEvents += events.timeEvents();
    res_.stats.jumps += events.jumps();
    return end;
  };
  // IDA and CVODE need stop > start; a zero-length run still initializes.
  // The variables computed outside the integrator are error-tested with
  // the algebraic unknowns (docs/runtime.md, "The error test").
  if (weighsComputed)
    integrator.weighErrors(&weights);
  auto ok =
      integrator.init(set, t, y.data(), yp.data(), s_.rtol, weights.atol(),
                      span > 0 ? s_.stop : s_.start + 1e-6, errorTestAlgebraic);
  if (!ok) {
    // The options were fine; a SUNDIALS call failing from here on is a
    // numerical failure of this run (status 3), never a command-line error.
    res_.failure = describeSolverError(t, ok.error());
    return done(StageEnd::Done);
  }
  auto init0 = std::chrono::steady_clock::now();
  bool initialized = true;
  IntegratorInitTarget initTarget(ev, integrator);
  if (fromStart) {
    InitOutcome init =
        initialize(ev, initTarget, set, t, firstOutput(t),
                   ContinuationKind::IfModelHasHomotopy, o_.log);
    initialized = init.ok;
    if (!init.ok)
      res_.failure = std::move(init.failure);
  } else {
    // The new mode's model from the point carried over: the jump rule,
    // nothing held (the old model's fixed start values are no conditions
    // here).
    std::vector<double> y0 = y, yp0 = yp;
    initialized =
        restartAfterEvent(ev, integrator, t, y0, yp0, {}, res_.failure, o_.log);
  }
  res_.stats.initTime +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - init0)
          .count();
  if (!initialized)
    return done(StageEnd::Done);
  events.setStateSet(integrator.set());
  if (!fromStart)
    events.noteJump(t, y,
                    std::vector<double>(integrator.y(), integrator.y() + n));
  y.assign(integrator.y(), integrator.y() + n);
  yp.assign(integrator.yp(), integrator.yp() + n);

  // The re-initialization after an event: the held point made consistent
  // with the new discrete values by the start's rule, the integrator
  // restarted there.
  Reinitialize reinit =
      [&](double te, std::vector<double> &ye, std::vector<double> &ype,
          const std::vector<int> &held, std::string &failure) {
        return restartAfterEvent(ev, integrator, te, ye, ype, held, failure,
                                 o_.log);
      };
  // The rows and the end of the run after an event; nothing when the run
  // goes on.
  auto concluded = [&](EventOutcome out) -> std::optional<StageEnd> {
    switch (out) {
    case EventOutcome::Unchanged:
    case EventOutcome::Restarted:
    case EventOutcome::Handled:
      return std::nullopt;
    case EventOutcome::ModeChange:
      carryOver(ev, t, y, yp, carry);
      return StageEnd::ModeChange;
    case EventOutcome::Failed:
      res_.failure = events.message();
      return StageEnd::Done;
    case EventOutcome::Terminated:
      if (o_.log)
        *o_.log << fmt::format("t = {:.10g}: terminate: {}; the run ends "
                               "here\n",
                               t, events.message());
      if (rec.record(t, y.data(), yp.data()) &&
          events.terminal(t, y.data(), yp.data()))
        rec.record(t, y.data(), yp.data());
      return StageEnd::Done;
    case EventOutcome::AtRest: {
      if (o_.log)
        *o_.log << events.message() << "\n";
      std::vector<double> still(n, 0.0);
      if (events.comeToRest(t, y, still) == EventOutcome::Failed) {
        res_.failure = events.message();
        return StageEnd::Done;
      }
      bool recorded = rec.record(t, y.data(), still.data());
      for (; recorded && k_ <= nOut_; ++k_)
        if (gridTime(k_) > t)
          recorded = rec.record(gridTime(k_), y.data(), still.data());
      if (recorded && rows_.lastTime() < s_.stop)
        recorded = rec.record(s_.stop, y.data(), still.data());
      if (recorded && events.terminal(s_.stop, y.data(), still.data()))
        rec.record(s_.stop, y.data(), still.data());
      return StageEnd::Done;
    }
    }
    return StageEnd::Done;
  };

  // The initialization's point with its round-off zeros made exact (the
  // initial event's relations read it), the integrator restarted there when
  // one moved.
  auto restartAtRoundOffZeros = [&](double te, std::vector<double> &ye,
                                    std::vector<double> &ype,
                                    std::string &failure) {
    if (!snapRoundOffZeros(ev, ye, ype, m.start_y, m.start_yp))
      return true;
    if (auto re = integrator.reinit(integrator.set(), te, ye.data(), ype.data());
        !re) {
      failure = describeSolverError(te, re.error());
      return false;
    }
    return true;
  };
  // At the initial event a discrete value that changes changes the
  // initialization problem itself (OpenModelica's eventTest2: `d = if a >
  // 1 then 1 else 2` with `initial equation a + d = 0`): it is solved
  // again from the start values with the new discrete values, so the
  // initial equations and fixed starts still hold. Fired reinits (held
  // values) follow the event's rule.
  Reinitialize reinitialize =
      [&](double te, std::vector<double> &ye, std::vector<double> &ype,
          const std::vector<int> &held, std::string &failure) {
        if (!held.empty())
          return reinit(te, ye, ype, held, failure);
        std::vector<double> y0(m.start_y, m.start_y + n),
            yp0(m.start_yp, m.start_yp + n);
        if (auto re =
                integrator.reinit(integrator.set(), te, y0.data(), yp0.data());
            !re) {
          failure = describeSolverError(te, re.error());
          return false;
        }
        InitOutcome again =
            initialize(ev, initTarget, integrator.set(), te, firstOutput(te),
                       ContinuationKind::None, o_.log);
        if (!again.ok) {
          failure = std::move(again.failure);
          return false;
        }
        ye = std::move(again.y);
        ype = std::move(again.yp);
        return restartAtRoundOffZeros(te, ye, ype, failure);
      };
  // IDA predicts its first step from y': an algebraic unknown that changes
  // at once (an acceleration driven by a sine torque through MSL's
  // Rotational.Examples.First, index 3) had y' = 0 there, and the error
  // test failed at every step size down to IDA's limit (the error grew as
  // 1/rtol). Its y' is the difference quotient of the point just ahead.
  // (An ODE's, CVODE's, unknowns are all differential: nothing to do.)
  if (fromStart && errorTestAlgebraic && span > 0 &&
      algebraicDerivatives(ev, integrator.set(), t, y, yp)) {
    if (auto re = integrator.reinit(integrator.set(), t, y.data(), yp.data());
        !re) {
      res_.failure = describeSolverError(t, re.error());
      return done(StageEnd::Done);
    }
  }
  if (fromStart && events.active() &&
      !restartAtRoundOffZeros(t, y, yp, res_.failure))
    return done(StageEnd::Done);
  EventOutcome first = fromStart ? events.initial(t, y, yp, reinitialize)
                                 : events.resume(t, y, yp, reinit);
  if (auto end = concluded(first))
    return done(*end);
  if (!rec.record(t, y.data(), yp.data()) || span <= 0)
    return done(StageEnd::Done);
  // A sample at the start time fires in an event of its own right after
  // the initial event: `when sample(0, 0.1)` counts at t = 0.
  if (fromStart && events.sampleInstantAt(t, y.data(), yp.data())) {
    EventOutcome out = events.handle(t, y, yp, /*timeEvent=*/true, reinit);
    if (out != EventOutcome::Unchanged && out != EventOutcome::Restarted) {
      if (auto end = concluded(out))
        return done(*end);
      if (!rec.record(t, y.data(), yp.data()))
        return done(StageEnd::Done);
    }
  }
  watch.restarted(t, y.data(), yp.data());

  // The integrator steps freely up to the stop time or the next time
  // event; output times it steps over are interpolated from the last
  // step's polynomial (computed variables are evaluated there by the
  // outputs function). A stop time per output would cost steps and
  // Jacobian refreshes (docs/runtime.md).
  double nextEvent = 0; // the time event the integrator stops at (or later)
  auto aimAtNextEvent = [&]() {
    nextEvent = events.nextTimeEvent(t, integrator.y(), integrator.yp());
    double aim = std::min(s_.stop, nextEvent);
    // A relation whose root function is zero here changes just after t,
    // unseen by the root finder: stop there to see it (RootWatch.h).
    if (events.handlesRoots())
      aim = std::min(aim, watch.stopAheadOfZero(t));
    auto ok = integrator.setStopTime(aim);
    if (!ok)
      res_.failure = describeSolverError(t, ok.error());
    return bool(ok);
  };
  if (!aimAtNextEvent())
    return done(StageEnd::Done);
  // A relation is watched at step ends only: no step longer than the
  // output interval, so that one crossing and crossing back within it
  // (sin(2 pi t) > 0.5 for a third of each period) is seen.
  if (events.handlesRoots() && m.n_roots > 0)
    if (auto capped = integrator.setMaxStep(s_.interval); !capped) {
      res_.failure = describeSolverError(t, capped.error());
      return done(StageEnd::Done);
    }
  int tinySteps = 0; // consecutive steps at round-off level
  double lastH = 0;  // the last step's size
  long stepsSinceOutput = 0;
  long foldJumpsSinceOutput = 0;
  std::vector<double> yAt(n), ypAt(n), cond;
  // The grid rows up to `tEnd` (where the solution is yEnd, ypEnd), from
  // the last step's polynomial; false (with the failure) when one cannot
  // be interpolated or the table is full.
  auto recordGridUpTo = [&](double tEnd, const double *yEnd,
                            const double *ypEnd) {
    for (; k_ <= nOut_ && gridTime(k_) <= tEnd; ++k_) {
      stepsSinceOutput = foldJumpsSinceOutput = 0;
      double tk = gridTime(k_);
      if (o_.everyStep)
        continue;
      if (tk == tEnd) {
        if (!rec.record(tEnd, yEnd, ypEnd))
          return false;
        continue;
      }
      auto at = integrator.interpolate(tk, yAt.data(), ypAt.data());
      if (!at) {
        res_.failure = describeSolverError(tk, at.error());
        return false;
      }
      // Out of the error test, an algebraic unknown's interpolant is no
      // approximation of it (an ideal diode conducting: c.v 1e-3 off
      // vs(t) between steps): solved from the interpolated states. Only
      // for an index-1 system (whose default is the test on): above index
      // one as written (--method raw) the states alone do not determine
      // the algebraic unknowns, and the solve would fail at every row.
      if (!errorTestAlgebraic && m.algebraic_error_test != 0)
        settleAlgebraic(ev, integrator.set(), tk, yAt, ypAt);
      if (!rec.record(tk, yAt.data(), ypAt.data()))
        return false;
    }
    return true;
  };
  // An algebraic solution that ends (a fold: the Schmitt trigger's op-amp
  // output saturated at one supply past its switching threshold, under
  // noEvent) fails the corrector at every step size there. Just past the
  // last point reached, the states held, the algebraic unknowns are solved
  // again as after an event; where they jump to another branch, the run
  // goes on from it (as Dymola's results for MSL's OpAmps examples do).
  // One attempt per point reached, and only a real jump counts.
  double lastFoldTry = -std::numeric_limits<double>::infinity();
  // A jump, not the iteration settling the same branch: some unknown
  // moved by a hundredth of its size.
  auto jumpedFar = [&](const std::vector<double> &from,
                       const std::vector<double> &to) {
    for (int i = 0; i < n; ++i)
      if (std::fabs(to[i] - from[i]) >
          1e-2 * std::max({std::fabs(from[i]), std::fabs(to[i]), 1e-6}))
        return true;
    return false;
  };
  auto jumpPastFold = [&](const StepStatus &st) {
    if (st.failure != FailureKind::Convergence &&
        st.failure != FailureKind::ErrorTest)
      return false;
    const double tc = integrator.currentTime();
    if (!(tc > lastFoldTry) || tc >= s_.stop)
      return false;
    lastFoldTry = tc;
    // Copied: every try restarts the integrator.
    const std::vector<double> yc(integrator.y(), integrator.y() + n),
        ypc(integrator.yp(), integrator.yp() + n);
    const double h0 = integrator.lastStep();
    const int *differential = ev.set(integrator.set()).is_differential;
    // Held explicitly: with none held, the re-initialization's nearest-point
    // fallback moves the states back to the fold, a consistent point of
    // the old branch, and the other branch is never tried.
    std::vector<int> statesHeld;
    for (int i = 0; i < n; ++i)
      if (differential[i])
        statesHeld.push_back(i);
    for (double h : {1e-3 * h0, 1e-2 * h0, 0.1 * h0, h0, 10 * h0}) {
      const double tt =
          std::min(tc + std::max(h, 1e-12 * (1 + std::fabs(tc))), s_.stop);
      std::vector<double> predicted(n);
      for (int i = 0; i < n; ++i)
        predicted[i] = yc[i] + (tt - tc) * ypc[i];
      // The damped Newton iteration from the old branch stops at the
      // residual's minimum near the fold; the other branch of a limiter
      // symmetric about zero (op-amp supplies +-15 V) is found from the
      // algebraic unknowns mirrored.
      // Only where the old branch has ended: while it still has a point
      // (a failure for another reason), the other branch of the
      // hysteresis is no answer.
      std::vector<double> yt = predicted, ypt = ypc;
      std::string why;
      if (restartAfterEvent(ev, integrator, tt, yt, ypt, statesHeld, why, nullptr)) {
        if (!jumpedFar(predicted, yt))
          continue;
      } else {
        yt = predicted;
        ypt = ypc;
        for (int i = 0; i < n; ++i)
          if (!differential[i])
            yt[i] = -yt[i];
        if (!restartAfterEvent(ev, integrator, tt, yt, ypt, statesHeld, why, nullptr) ||
            !jumpedFar(predicted, yt))
          continue;
      }
      if (o_.log) {
        *o_.log << fmt::format("t = {:.10g}: the algebraic equations have no "
                               "solution near the point reached at t = "
                               "{:.10g} (a fold); solved again with the "
                               "states held, they jumped:\n",
                               tt, tc);
        reportMoves(ev, predicted, yt.data(), o_.log);
      }
      t = tt;
      // Grid rows the jump stepped over take the new branch.
      for (; k_ <= nOut_ && gridTime(k_) < tt; ++k_)
        if (!o_.everyStep && !rec.record(gridTime(k_), yt.data(), ypt.data()))
          return false;
      if (!rec.record(tt, yt.data(), ypt.data()))
        return false;
      watch.restarted(t, yt.data(), ypt.data());
      stepsSinceOutput = 0;
      if (++foldJumpsSinceOutput > kMaxFoldJumpsPerOutput) {
        res_.failure = describeFailure(
            ev, integrator,
            StepStatus::failed(
                FailureKind::TooMuchWork,
                fmt::format("more than {} jumps past a fold of the algebraic "
                            "equations between output times (an oscillation "
                            "far faster than the output interval)",
                            kMaxFoldJumpsPerOutput)),
            t);
        return false;
      }
      return aimAtNextEvent();
    }
    return false;
  };
  while (true) {
    StepStatus st = integrator.step(t);
    // A step growing from a tiny first one after a restart (IDA's h0 =
    // 0.5 / ||y'||, then doubling) is no collapse: a tiny step that grows
    // is not counted. It does not reset the count either: near a
    // singularity the steps shrink with a success's growth between them.
    const double h = integrator.lastStep();
    if (!st.ok() || h > 1e4 * 2.2e-16 * std::fabs(t))
      tinySteps = 0;
    else if (!(h > 1.5 * lastH))
      ++tinySteps;
    lastH = h;
    if (tinySteps > 20)
      st = StepStatus::failed(FailureKind::StepCollapsed, "step size collapse");
    if (st.ok() && ++stepsSinceOutput > kMaxStepsPerOutput)
      st = StepStatus::failed(
          FailureKind::TooMuchWork,
          fmt::format("more than {} steps between output times",
                      kMaxStepsPerOutput));
    if (!st.ok()) {
      // Described before a jump is tried, which restarts the integrator.
      std::string failure =
          describeFailure(ev, integrator, st, integrator.currentTime());
      if (jumpPastFold(st))
        continue;
      if (res_.failure.empty())
        res_.failure = std::move(failure);
      return done(StageEnd::Done);
    }
    bool recorded =
        (!o_.everyStep || rec.record(t, integrator.y(), integrator.yp())) &&
        recordGridUpTo(t, integrator.y(), integrator.yp());
    if (!recorded)
      return done(StageEnd::Done);
    // With --every-step each step is an output: the limit on steps between
    // output times is not the default grid's (--stop 8e6 --every-step ran
    // into it at t = 12279).
    if (o_.everyStep)
      stepsSinceOutput = foldJumpsSinceOutput = 0;
    bool timeEvent = st.kind == StepStatus::StopReached && t >= nextEvent;
    bool rootEvent = st.kind == StepStatus::Root && events.handlesRoots();
    bool forced = false; // a crossing ignored as round-off was real
    if (rootEvent && watch.withinRoundOff(integrator.rootsFound())) {
      rootEvent = false;
    } else if (!rootEvent && events.handlesRoots())
      forced = watch.stepped(t, integrator.y(), integrator.yp());
    if (st.kind == StepStatus::Root && !events.handlesRoots() && o_.log) {
      std::vector<int> found = integrator.rootsFound();
      for (size_t r = 0; r < found.size(); ++r)
        if (found[r])
          *o_.log << fmt::format("t = {:.10g}: event condition {} crossed "
                                 "zero\n",
                                 t, r + 1);
    }
    if (timeEvent || rootEvent || forced) {
      // The row just before the event (unless a grid row is at t), kept
      // only when the event changes something.
      y.assign(integrator.y(), integrator.y() + n);
      yp.assign(integrator.yp(), integrator.yp() + n);
      double tRoot = t;
      if (rootEvent) {
        pastTheRoots(ev, integrator, t, y, yp);
        // A grid time the move stepped over (a sine source's zero at an
        // output time) still belongs to the old mode, and the integrator
        // restarted at t could not reach back to it.
        if (!recordGridUpTo(t, y.data(), yp.data()))
          return done(StageEnd::Done);
      }
      size_t rows = rows_.size();
      if ((rows == 0 || rows_.lastTime() != t) &&
          !rec.record(t, y.data(), yp.data()))
        return done(StageEnd::Done);
      const long jumpsBefore = events.jumps();
      EventOutcome out = events.handle(t, y, yp, timeEvent, reinit);
      if (out == EventOutcome::Handled && rootEvent &&
          events.jumps() == jumpsBefore)
        if (int j = watch.sliding(t, integrator.rootsFound(), kChatterEvents,
                                  s_.interval);
            j >= 0) {
          res_.failure = slidingMessage(ev, j, t, watch.slidingSince(j));
          return done(StageEnd::Done);
        }
      if (out == EventOutcome::Unchanged) {
        rows_.truncate(rows);
        t = tRoot; // the integrator goes on from where it stopped
      } else if (out == EventOutcome::Restarted) {
        rows_.truncate(rows);
      } else if (auto end = concluded(out))
        return done(*end);
      else if (!rec.record(t, y.data(), yp.data()))
        return done(StageEnd::Done);
      if (out != EventOutcome::Unchanged)
        watch.restarted(t, y.data(), yp.data());
      if ((st.kind == StepStatus::StopReached ||
           out != EventOutcome::Unchanged) &&
          !aimAtNextEvent())
        return done(StageEnd::Done);
      stepsSinceOutput = 0;
    } else if (st.kind == StepStatus::StopReached && t < s_.stop &&
               !aimAtNextEvent()) {
      return done(StageEnd::Done); // stopped just after a zero (RootWatch)
    }
    // On to the stop time also past the last of --output-times: the
    // last row is the stop time's, from the integrator there (it was
    // interpolated from a step that an event had cut short of it).
    if (t >= s_.stop || atStopTime(t))
      break;
    if (m.n_state_sets > 1) {
      cond = pivotConditions(ev, t, integrator.y(), integrator.yp());
      int best = chooseStateSet(cond, integrator.set());
      if (best != integrator.set() &&
          !switchStates(ev, integrator, best, t,
                        std::min(s_.stop, t + s_.interval), cond, res_, o_.log))
        return done(StageEnd::Done);
      events.setStateSet(integrator.set());
    }
    if (m.n_dynamic_sets > 0 &&
        !reselectStates(ev, integrator, t, std::min(s_.stop, t + s_.interval),
                        res_, o_.log))
      return done(StageEnd::Done);
    if (interrupted(t))
      return done(StageEnd::Done);
    progress_.update(t);
  }
  // The last row is the stop time's; then the terminal event.
  if (rows_.lastTime() < s_.stop && atStopTime(t)) {
    if (!rec.record(s_.stop, integrator.y(), integrator.yp()))
      return done(StageEnd::Done);
  } else if (rows_.lastTime() < s_.stop) {
    auto at = integrator.interpolate(s_.stop, yAt.data(), ypAt.data());
    if (!at) {
      res_.failure = describeSolverError(s_.stop, at.error());
      return done(StageEnd::Done);
    }
    if (!rec.record(s_.stop, yAt.data(), ypAt.data()))
      return done(StageEnd::Done);
  }
  if (events.terminal(t, integrator.y(), integrator.yp()))
    rec.record(t, integrator.y(), integrator.yp());
  progress_.finish();
  return done(StageEnd::Done);
}

} // namespace

double outputRows(double start, double stop, double interval) {
  // In double: a tiny interval overflows a long.
  return 1 + std::max(1.0, std::ceil((stop - start) / interval - 1e-9));
}

std::string tooManyRowsMessage(double start, double stop, double interval) {
  return fmt::format("the output interval {} from {} to {} gives {:.3g} rows, "
                     "more than the limit of {:.0e}; use a larger --interval",
                     interval, start, stop, outputRows(start, stop, interval),
                     kMaxOutputRows);
}

/// The model of the mode `values` among those compiled ahead (ABI 12).
static Expected<const ldae_model *> compiledMode(const ldae_model &m,
                                          const std::vector<double> &values) {
  for (int j = 0; j < m.n_mode_models; ++j) {
    const double *v = m.mode_model_values + size_t(j) * m.n_mode;
    if (std::equal(values.begin(), values.end(), v, v + m.n_mode))
      return m.mode_models[j];
  }
  return Error{"the program has no model of it (ldaec --emit c compiles "
               "every mode it can analyse; this one it could not)"};
}

Expected<SimResult> simulate(const ldae_model &m, const SimOptions &o) {
  auto wall0 = std::chrono::steady_clock::now();
  if (m.abi_version != LDAE_ABI_VERSION)
    return Error{fmt::format("model ABI version {} does not match the "
                             "runtime's {}",
                             m.abi_version, LDAE_ABI_VERSION)};
  if (m.n_state_sets < 1 || !m.state_sets)
    return Error{"the model has no state set"};
  auto settings = resolve(m, o);
  if (!settings)
    return Error{settings.error()};
  const RunSettings &s = *settings;
  // The model as this run changes it: parameters, what they bind, starts.
  auto bound = bindValues(m, o.params, o.starts, s.start);
  if (!bound)
    return Error{bound.error()};
  const std::vector<double> *params = &bound->p;
  ldae_model changed = m;
  changed.param_values = bound->p.data();
  changed.start_y = bound->y.data();

  auto chosen = chooseColumns(m, o.outputs);
  if (!chosen)
    return Error{chosen.error()};
  std::vector<int> cols = std::move(*chosen);
  std::vector<std::string> available = Reportable(m).names;

  SimResult res;
  RowLog rows(res, o.rowSink);
  res.model = m.name ? m.name : "";
  res.columns.push_back("time");
  for (int c : cols)
    res.columns.push_back(available[c]);
  res.info = columnInfo(m, cols);
  res.params = parameterValues(m, params->data());
  res.stats.n = m.n;
  auto finish = [&]() -> Expected<SimResult> {
    rows.finish();
    res.stats.wallTime =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0)
            .count();
    if (!res.failure.empty())
      res.status = 3;
    // Called once, as the run returns: the rows are handed over, not
    // copied (a run held in memory would need them twice at its peak).
    return std::move(res);
  };

  if (!bound->failure.empty()) {
    res.failure = fmt::format("t = {:.10g}: {}", s.start, bound->failure);
    return finish();
  }
  Run run(o, s, res, rows);
  if (m.n == 0) {
    run.closedForm(changed, *params, cols);
    return finish();
  }
  // A variable-structure model runs one stage per mode reached, each with
  // the model of its mode, the point carried over by name.
  const ldae_model *model = &changed;
  std::vector<double> p = *params;
  Carry carry;
  // Mode switches at one time continue one event iteration: the same
  // limit of updates (an ideal diode whose conditions read round-off at
  // its switching point would switch for ever).
  int switchesHere = 0;
  double switchTime = NAN;
  std::deque<double> recentSwitches; // times of the latest mode switches
  // Without a compiler (the program of --emit c) the modes compiled ahead
  // are in the model.
  auto provider = o.modeProvider;
  if (!provider && m.n_mode_models > 0)
    provider = [&m](const std::vector<double> &values) {
      return compiledMode(m, values);
    };
  while (true) {
    auto end = run.stage(*model, p, cols, carry);
    if (!end)
      return Error{end.error()};
    if (*end == StageEnd::Done)
      break;
    if (!provider) {
      res.failure = fmt::format(
          "t = {:.10g}: the mode changed ({}) and the run has no model of the "
          "new mode (no mode provider)",
          carry.t, carry.mode);
      break;
    }
    auto next = provider(carry.modeValues);
    if (!next) {
      res.failure = fmt::format("t = {:.10g}: the model of the new mode ({}) "
                                "cannot be built: {}",
                                carry.t, carry.mode, next.error());
      break;
    }
    model = *next;
    if (model->n == 0) {
      // SUNDIALS takes no empty system, and the walk without unknowns
      // (Run::closedForm) starts only at the start time.
      res.failure = fmt::format(
          "t = {:.10g}: the new mode ({}) leaves no unknown to integrate "
          "(every variable is fixed by its equations); a run that enters "
          "such a mode is not supported",
          carry.t, carry.mode);
      break;
    }
    auto np = modeParams(*model, o, carry.t);
    std::vector<std::string> names = Reportable(*model).names;
    std::vector<int> nextCols;
    for (size_t c = 1; c < res.columns.size() && np; ++c) {
      auto it = std::find(names.begin(), names.end(), res.columns[c]);
      if (it == names.end()) {
        np = Error{fmt::format("it does not report '{}'", res.columns[c])};
        break;
      }
      nextCols.push_back(int(it - names.begin()));
    }
    if (!np) {
      res.failure = fmt::format("t = {:.10g}: the model of the new mode ({}) "
                                "does not fit the run: {}",
                                carry.t, carry.mode, np.error());
      break;
    }
    p = *np;
    cols = nextCols;
    ++res.stats.modeSwitches;
    switchesHere = carry.t == switchTime ? switchesHere + 1 : 1;
    switchTime = carry.t;
    // Chattering between modes: each switch starts another stage, whose
    // event loop sees none of the others (a mutant of the stick-slip model
    // switched every 1.5e-8 s until its CPU time ran out).
    recentSwitches.push_back(carry.t);
    if (recentSwitches.size() > kChatterEvents + 1)
      recentSwitches.pop_front();
    if (recentSwitches.size() > kChatterEvents &&
        carry.t - recentSwitches.front() <
            kChatterSpan * (1 + std::fabs(carry.t))) {
      res.failure = fmt::format(
          "chattering at t = {:.10g}: {} mode switches within {:.3g} s; the "
          "mode values that keep changing: {}",
          carry.t, recentSwitches.size(), carry.t - recentSwitches.front(),
          carry.mode);
      break;
    }
    if (switchesHere > kMaxModeSwitchesAtOnce) {
      res.failure = fmt::format(
          "the event iteration at t = {:.10g} switched modes {} times "
          "without settling; the mode values that keep changing: {}",
          carry.t, kMaxModeSwitchesAtOnce, carry.mode);
      break;
    }
    if (o.log)
      *o.log << fmt::format("t = {:.10g}: mode switch ({})\n", carry.t,
                            carry.mode);
  }
  return finish();
}

void printStats(const SimStats &st, std::ostream &out) {
  out << fmt::format("integrator                  {}\n", st.integrator)
      << fmt::format("unknowns                    {}\n", st.n)
      << fmt::format("linear solver               {}\n",
                     st.sparse ? "KLU (sparse)" : "dense LU")
      << fmt::format("steps                       {}\n", st.steps)
      << fmt::format("residual evaluations        {}\n", st.residualEvals)
      << fmt::format("jacobian evaluations        {}\n", st.jacobianEvals)
      << fmt::format("error test failures         {}\n", st.errorTestFailures)
      << fmt::format("nonlinear conv. failures    {}\n", st.convergenceFailures)
      << fmt::format("state set switches          {}\n", st.stateSwitches)
      << fmt::format("roots found                 {}\n", st.rootsFound)
      << fmt::format("events                      {}\n", st.events)
      << fmt::format("time events                 {}\n", st.timeEvents)
      << fmt::format("mode switches               {}\n", st.modeSwitches)
      << fmt::format("jumps                       {}\n", st.jumps)
      << fmt::format("largest drift residual      {:.3g}\n", st.maxDrift);
  if (st.projections > 0)
    out << fmt::format("constraint projections      {}\n", st.projections);
  out << fmt::format("initialization time         {:.6f} s\n", st.initTime)
      << fmt::format("wall time                   {:.6f} s\n", st.wallTime);
}

} // namespace ldae::runtime
