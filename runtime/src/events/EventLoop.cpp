// Event handling (see EventLoop.h and docs/events.md).
#include "events/EventLoop.h"
#include "events/RelationSearch.h"
#include "events/RoundOffZeros.h"
#include "init/ConsistentInit.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <ostream>

namespace ldae::runtime {

namespace {

/// Updates without reaching a fixed point before the iteration is a failure.
constexpr int kMaxIterations = 100;
/// The span relative to 1 + |t| below which the predicted remaining time
/// of a geometric accumulation (Zeno) counts as reached.
constexpr double kZenoSpan = 1e-9;
/// Zeno: this many consecutive events with a reinit, spaced ever closer.
constexpr size_t kZenoEvents = 12;

bool differs(double a, double b) {
  return a != b && !(std::isnan(a) && std::isnan(b));
}

} // namespace

EventLoop::EventLoop(ModelEval &ev, double rtol, std::ostream *log)
    : ev_(ev), m_(ev.model()), nd_(std::max(ev.model().n_discrete, 0)),
      rtol_(rtol), log_(log), delays_(ev.model()),
      reinitScale_(std::max(ev.model().n_reinit, 0), 0.0) {
  if (nd_ > 0)
    out_.resize(nd_ + 2 * std::max(m_.n_reinit, 0) +
                std::max(m_.n_terminate, 0));
}

std::vector<double> EventLoop::timeEventValues(double t, const double *y,
                                               const double *yp) const {
  int nth = std::max(m_.n_time_thresholds, 0), ns = std::max(m_.n_samples, 0);
  std::vector<double> te(nth + 2 * ns + 3 * delays_.size());
  if (!active() || !m_.time_events || te.empty() ||
      m_.time_events(t, y, yp, ev_.params(), te.data()) != 0)
    te.clear();
  return te;
}

double EventLoop::nextTimeEvent(double t, const double *y,
                                const double *yp) const {
  double next = delays_.next(t);
  int nth = std::max(m_.n_time_thresholds, 0), ns = std::max(m_.n_samples, 0);
  if (nth + ns == 0)
    return next;
  std::vector<double> te = timeEventValues(t, y, yp);
  if (te.empty())
    return next;
  for (int i = 0; i < nth; ++i)
    if (te[i] > t)
      next = std::min(next, te[i]);
  for (int s = 0; s < ns; ++s) {
    double s0 = te[nth + 2 * s], iv = te[nth + 2 * s + 1];
    if (!(iv > 0) || !std::isfinite(s0))
      continue;
    // start + k * interval, never accumulated: the instants stay exact.
    double k = std::max(0.0, std::ceil((t - s0) / iv));
    for (int tries = 0; tries < 4 && s0 + k * iv <= t; ++tries)
      k += 1;
    // An interval below the resolution of time at t (sample(0.1, 1e-308))
    // has no next instant after t: the closest time is the next, and the
    // chattering check names the clause (counting until an instant after
    // t hung the run).
    double at = s0 + k * iv;
    next = std::min(next, at > t ? at : std::nextafter(t, HUGE_VAL));
  }
  return next;
}

bool EventLoop::sampleInstant(int s, double t, const double *y,
                              const double *yp) const {
  int nth = std::max(m_.n_time_thresholds, 0);
  std::vector<double> te = timeEventValues(t, y, yp);
  if (te.empty())
    return false;
  double s0 = te[nth + 2 * s], iv = te[nth + 2 * s + 1];
  if (!(iv > 0) || t < s0)
    return false;
  double k = std::round((t - s0) / iv);
  return std::fabs(s0 + k * iv - t) <= 4e-16 * std::max(1.0, std::fabs(t));
}

bool EventLoop::sampleInstantAt(double t, const double *y,
                                const double *yp) const {
  for (int s = 0; active() && s < m_.n_samples; ++s)
    if (sampleInstant(s, t, y, yp))
      return true;
  return false;
}

bool EventLoop::update(double t, const double *y, const double *yp) {
  if (!m_.event_update ||
      m_.event_update(t, y, yp, ev_.params(), out_.data()) != 0)
    return false;
  // A change of mode is decided by the right limit: the discrete values
  // just after t. At an ideal diode's turn-off the blocking mode's
  // v = vs - vc is +1e-16 with zero slope, and `when v > 0` would switch it
  // straight back for ever; just after t, v < 0. The point ahead is
  // y + dt y' with the algebraic unknowns solved there; dt = sqrt(eps)
  // (1 + |t|) takes a relation that leaves zero to second order well past
  // round-off. The reinit values stay those at t.
  auto changesMode = [&](const std::vector<double> &out) {
    for (int i = 0; i < m_.n_mode; ++i)
      if (differs(out[m_.mode_discrete[i]], m_.mode_values[i]))
        return true;
    return false;
  };
  if (m_.n_mode == 0 || !changesMode(out_))
    return true;
  const int n = ev_.n();
  double dt = 1.4901161193847656e-08 * (1.0 + std::fabs(t));
  std::vector<double> ahead(n), aheadYp(yp, yp + n), probe(out_.size());
  for (int i = 0; i < n; ++i)
    ahead[i] = y[i] + dt * yp[i];
  settleAlgebraic(ev_, set_, t + dt, ahead, aheadYp);
  if (m_.event_update(t + dt, ahead.data(), aheadYp.data(), ev_.params(),
                      probe.data()) == 0 &&
      !changesMode(probe))
    std::copy(probe.begin(), probe.begin() + nd_, out_.begin());
  return true;
}

void EventLoop::setKind(int kind, double v) {
  for (int k = 0; k < nd_; ++k)
    if (m_.discrete_kind && m_.discrete_kind[k] == kind)
      ev_.discrete()[k] = v;
}

std::string EventLoop::namesOf(const std::vector<bool> &which) const {
  std::string s;
  for (int k = 0; k < nd_; ++k)
    if (which[k])
      s += (s.empty() ? "" : ", ") + ev_.quotedDiscreteName(k);
  return s.empty() ? "none" : s;
}

bool EventLoop::modeChanged() const {
  for (int i = 0; i < m_.n_mode; ++i)
    if (differs(ev_.discrete()[m_.mode_discrete[i]], m_.mode_values[i]))
      return true;
  return false;
}

std::vector<double> EventLoop::modeValues() const {
  std::vector<double> v;
  for (int i = 0; i < m_.n_mode; ++i)
    v.push_back(ev_.discrete()[m_.mode_discrete[i]]);
  return v;
}

void EventLoop::noteJump(double t, const std::vector<double> &before,
                         const std::vector<double> &after) {
  std::string moved;
  int count = 0;
  for (int i = 0; i < ev_.n(); ++i) {
    // States only: algebraic values may follow a discrete change anyway.
    double scale = std::max(std::fabs(before[i]), std::fabs(after[i]));
    // A value within round-off of 0 made exact is no jump (RoundOffZeros.h).
    double nominal = m_.nominal ? m_.nominal[i] : 1.0;
    if ((states_ && !states_[i]) || !differs(before[i], after[i]) ||
        std::fabs(before[i] - after[i]) <= 1e-13 * scale ||
        (after[i] == 0 && std::fabs(before[i]) <= kRoundOffZero * nominal))
      continue;
    if (++count <= 8)
      moved += fmt::format("{}{} {:.10g} -> {:.10g}", moved.empty() ? "" : ", ",
                           ev_.varName(i), before[i], after[i]);
  }
  if (count == 0)
    return;
  ++jumps_;
  if (log_)
    *log_ << fmt::format("t = {:.10g}: jump: {}{}\n", t, moved,
                         count > 8 ? fmt::format(" and {} more", count - 8)
                                   : std::string());
}

bool EventLoop::observed(double t, const std::vector<double> &y,
                         const std::vector<double> &yp,
                         const std::vector<double> &readBefore) {
  // A delayed expression that moved shows d later: the run restarts and
  // aims at that instant (DelayLine.h) even when nothing reads it now.
  if (!delays_.empty()) {
    std::vector<double> te = timeEventValues(t, y.data(), yp.data());
    if (!te.empty() && delays_.moved(te.data()))
      return true;
  }
  std::vector<double> now = readings(t, y, yp, ev_.discrete(), nullptr, true);
  if (now.empty() || readBefore.size() != now.size())
    return true;
  for (size_t i = 0; i < now.size(); ++i)
    if (differs(now[i], readBefore[i]))
      return true;
  return false;
}

std::vector<double> EventLoop::readings(double t, const std::vector<double> &y,
                                        const std::vector<double> &yp,
                                        double *slots, const double *with,
                                        bool outputs) {
  std::vector<double> kept(slots, slots + nd_);
  if (with)
    std::copy(with, with + nd_, slots);
  int no = outputs ? m_.n_outputs : 0;
  std::vector<double> into(size_t(ev_.n()) * m_.n_state_sets + no, 0.0);
  int rc = 0;
  for (int k = 0; k < m_.n_state_sets; ++k)
    rc |= ev_.residual(k, t, y.data(), yp.data(), into.data() + k * ev_.n());
  if (no > 0 && m_.outputs)
    rc |= m_.outputs(t, y.data(), yp.data(), ev_.params(),
                     into.data() + ev_.n() * m_.n_state_sets);
  std::copy(kept.begin(), kept.end(), slots);
  if (rc != 0)
    into.clear();
  return into;
}

bool EventLoop::reads(double t, const std::vector<double> &y,
                      const std::vector<double> &yp, double *slots,
                      const double *against, bool outputs) {
  std::vector<double> now = readings(t, y, yp, slots, nullptr, outputs);
  std::vector<double> then = readings(t, y, yp, slots, against, outputs);
  if (now.empty() || then.empty())
    return true;
  for (size_t i = 0; i < now.size(); ++i)
    if (differs(now[i], then[i]))
      return true;
  return false;
}

bool EventLoop::contradictedNow(
    const std::vector<std::vector<double>> &contradicted, size_t from) const {
  const double *cur = ev_.discrete();
  return std::any_of(contradicted.begin() + from, contradicted.end(),
                     [&](const std::vector<double> &values) {
                       return std::equal(
                           values.begin(), values.end(), cur,
                           [](double a, double b) { return !differs(a, b); });
                     });
}

bool EventLoop::reproduces(double t, const std::vector<double> &y,
                           const std::vector<double> &yp) {
  if (!update(t, y.data(), yp.data()))
    return false;
  return std::equal(out_.begin(), out_.begin() + nd_, ev_.discrete(),
                    [](double a, double b) { return !differs(a, b); });
}

bool EventLoop::onlyRelations(const std::vector<bool> &changed) const {
  bool relations = m_.discrete_kind != nullptr;
  for (int k = 0; relations && k < nd_; ++k)
    relations = !changed[k] || m_.discrete_kind[k] == LDAE_DISCRETE_RELATION;
  return relations;
}

EventOutcome EventLoop::iterate(double t, std::vector<double> &y,
                                std::vector<double> &yp,
                                const Reinitialize &reinit) {
  const int nr = std::max(m_.n_reinit, 0), nt = std::max(m_.n_terminate, 0);
  double *cur = ev_.discrete();
  std::vector<double> before = y, entry(cur, cur + nd_);
  // A delayed value released at this time event (DelayLine.h) is already
  // in place, and the update copies it: its change is against pre(), its
  // value before the event (which later rounds move along with it).
  auto delayed = [&](int k) {
    return m_.discrete_kind && m_.discrete_kind[k] == LDAE_DISCRETE_DELAY;
  };
  for (int k = 0; k < nd_; ++k)
    if (delayed(k))
      entry[k] = ev_.pre()[k];
  std::vector<bool> changedAny(nd_, false), changed(nd_);
  std::vector<double> fired(nr, std::numeric_limits<double>::quiet_NaN());
  bool visible = false;
  std::string terminated;
  // The discrete values each solved point changed: coming back to one of
  // them is a cycle (RelationSearch.h), searched once.
  std::vector<std::vector<double>> contradicted;
  // Those since pre() last moved: a cycle among them is one at fixed
  // pre(), of the mixed system itself.
  size_t sincePre = 0;
  std::vector<double> solvedWith;
  bool searched = false;
  // The discrete values (t, y, y') was last made consistent with, or that
  // it reads no differently: pre() at the first round, then the values
  // of the round before.
  std::vector<double> last(ev_.pre(), ev_.pre() + nd_);
  // Whether pre() has not moved since the point was last solved: the
  // mixed system is being solved at fixed pre() (below).
  bool atFixedPre = false;
  // Whether the rounds still solve at fixed pre() (below).
  bool fixedPre = true;
  // pre(v) := v. An equation that reads pre() is another equation now
  // (a friction element's `locked` reads pre(mode)): the point is solved
  // again, its reinit targets `held`, before the next update reads it, and
  // so the integrator restarts from a point consistent with pre() = v.
  auto advancePre = [&](const std::vector<int> &held) {
    std::vector<double> old(ev_.pre(), ev_.pre() + nd_);
    std::copy(cur, cur + nd_, ev_.pre());
    atFixedPre = false;
    sincePre = contradicted.size();
    if (!reads(t, y, yp, ev_.pre(), old.data(), false))
      return true;
    std::string failure;
    if (!reinit(t, y, yp, held, failure)) {
      message_ = failure;
      return false;
    }
    visible = true;
    solvedWith.assign(cur, cur + nd_);
    return true;
  };
  for (int iter = 0;; ++iter) {
    if (iter > 0)
      last.assign(cur, cur + nd_);
    // What the point reads at the values of the round before, taken before
    // the update runs: an external object's state may move with it (the
    // MSL's CombiTimeTable advances its event interval in
    // getNextTimeEvent, and from then on reads its old next event time as
    // the new interval), so evaluated again afterwards with those values
    // it would read the new ones, and a stop button pressed at a table's
    // time event went unseen in ControlledTanks.
    const std::vector<double> readBefore =
        readings(t, y, yp, cur, last.data(), true);
    if (!update(t, y.data(), yp.data())) {
      message_ = fmt::format("the event update could not be evaluated at t "
                             "= {:.10g}",
                             t);
      return EventOutcome::Failed;
    }
    const double *next = out_.data(), *value = next + nd_,
                 *didFire = value + nr, *term = didFire + nr;
    std::vector<int> held;
    for (int r = 0; r < nr; ++r)
      if (didFire[r] != 0) {
        y[m_.reinit_target[r]] = value[r];
        held.push_back(m_.reinit_target[r]);
        fired[r] = value[r];
      }
    for (int i = 0; i < nt; ++i)
      if (term[i] != 0 && terminated.empty())
        terminated = m_.terminate_message && m_.terminate_message[i]
                         ? m_.terminate_message[i]
                         : "terminate()";
    bool any = false;
    for (int k = 0; k < nd_; ++k) {
      changed[k] = differs(next[k], cur[k]) ||
                   (iter == 0 && delayed(k) && differs(next[k], ev_.pre()[k]));
      any |= changed[k];
      if (changed[k])
        changedAny[k] = true;
      cur[k] = next[k];
    }
    if (!any && held.empty()) {
      // The point solved with these values gives them back at these pre()
      // values: the mixed system is solved. Only now pre(v) := v, and the
      // iteration goes on until that moves nothing (MLS 8.6).
      if (!atFixedPre ||
          std::equal(cur, cur + nd_, ev_.pre(),
                     [](double a, double b) { return !differs(a, b); }))
        break;
      if (!advancePre({}))
        return EventOutcome::Failed;
      continue;
    }
    if (!solvedWith.empty())
      contradicted.push_back(std::move(solvedWith));
    solvedWith.clear();
    if (iter + 1 >= kMaxIterations) {
      message_ = fmt::format(
          "the event iteration at t = {:.10g} found no fixed point after {} "
          "updates; the discrete values that keep changing: {}",
          t, kMaxIterations, namesOf(changed));
      return EventOutcome::Failed;
    }
    // The old model's structure does not hold in the new mode: the new
    // model re-initializes (and iterates on).
    if (modeChanged())
      break;
    // A cycle through relation values, or one at fixed pre() through
    // other values too: the mixed system has no fixed point this
    // iteration reaches; its Boolean unknowns are searched
    // (RelationSearch.h), once, and the iteration goes on from the
    // consistent combination at the same pre() values. A change that
    // neither a residual nor an output reads (a relation that only guards
    // a when-clause, crossing back) needs no restart and shows in no row.
    const bool relationsOnly = onlyRelations(changed);
    if (held.empty() && !searched && m_.discrete_kind &&
        (relationsOnly
             ? contradictedNow(contradicted, 0)
             : atFixedPre && contradictedNow(contradicted, sincePre))) {
      searched = true;
      std::vector<int> cycling;
      for (int k = 0; k < nd_; ++k)
        if (changed[k])
          cycling.push_back(k);
      if (relationsOnly && !chooseConsistentRelations(
                               ev_, set_, t, y, yp, cycling, reinit, message_))
        return EventOutcome::Failed;
      std::string failure;
      if (!relationsOnly &&
          !chooseConsistentValues(ev_, set_, t, y, yp, cycling, last, reinit,
                                  failure)) {
        // No combination holds at these pre() values (or several do): a
        // friction element whose driving torque is its largest sticking
        // torque to round-off (MSL's LossyGearDemo2 at t = 0.0636, the
        // bearing's locked point saying "start forward", the forward
        // point, held by the locked gear, giving sa = tau0_max exactly).
        // The iteration goes on as Dymola's does, pre(v) := v after each
        // round (the search left the point solved with these values); it
        // reaches Forward there, as the reference does.
        fixedPre = false;
        visible = true;
        if (!advancePre({}))
          return EventOutcome::Failed;
        continue;
      }
      for (int k = 0; k < nd_; ++k)
        if (differs(cur[k], entry[k]))
          changedAny[k] = true;
      visible = true;
      atFixedPre = true;
      continue;
    } else if (!held.empty() || observed(t, y, yp, readBefore)) {
      // Whether the discrete equations give these values back at the
      // point they were evaluated on (below).
      bool settledHere = held.empty() && reproduces(t, y, yp);
      std::string failure;
      if (!reinit(t, y, yp, held, failure)) {
        message_ = failure;
        return EventOutcome::Failed;
      }
      visible = true;
      solvedWith.assign(cur, cur + nd_);
      // The values were evaluated on a point solved with the old ones:
      // they are evaluated again on the new point at the same pre()
      // values until they give themselves back, and only that fixed
      // point moves pre() (MLS 8.6). Moving pre() after each round ran a
      // state machine on values of a point not yet solved: MSL's
      // Rotational Friction clutch reaching w_rel = 0 backward went to
      // Stuck, then, with pre(mode) = Stuck, read the backward sliding
      // point's sa as a start forward, and from there (each sliding
      // point's sa starting the other way) went Forward, Backward, ... at
      // one instant until the chattering check; at fixed pre() that is a
      // cycle, and the search above finds `locked`.
      // A fired reinit's value is taken once: evaluated again on its own
      // point, reinit(v, -e*v) would reverse v twice. Values that the
      // update does not give back even at the point they were evaluated
      // on loop through the discrete equations themselves (MSL's Digital
      // Pulse: `sampling = np < 3` guards the when-clause that counts
      // np): no value is a fixed point there at fixed pre(), and such a
      // loop goes on with pre(v) := v, as Dymola's event iteration
      // breaks it.
      if (settledHere && fixedPre) {
        atFixedPre = true;
        continue;
      }
    }
    if (!advancePre(held))
      return EventOutcome::Failed;
  }
  if (!visible && terminated.empty() && !modeChanged())
    return EventOutcome::Unchanged;
  // Back where it started (an ideal diode at its switching point, where
  // the new mode's relation reads round-off and switches back): the
  // integrator was restarted, but nothing happened.
  bool net = std::any_of(fired.begin(), fired.end(),
                         [](double v) { return !std::isnan(v); }) ||
             !terminated.empty();
  for (int k = 0; k < nd_; ++k)
    net |= differs(entry[k], cur[k]);
  if (!net)
    return EventOutcome::Restarted;
  noteJump(t, before, y);
  recent_.push_back({t, changedAny, fired});
  if (recent_.size() > kChatterEvents + 1)
    recent_.pop_front();
  if (!terminated.empty()) {
    message_ = terminated;
    return EventOutcome::Terminated;
  }
  if (modeChanged())
    return EventOutcome::ModeChange;
  return checkAccumulation(t, y, fired);
}

EventOutcome EventLoop::checkAccumulation(double t, std::vector<double> &y,
                                          const std::vector<double> &fired) {
  for (size_t r = 0; r < fired.size(); ++r)
    if (!std::isnan(fired[r]))
      reinitScale_[r] = std::max(reinitScale_[r], std::fabs(fired[r]));
  double span = kZenoSpan * (1 + std::fabs(t));
  std::vector<const Recent *> withReinit;
  for (const Recent &e : recent_)
    if (std::any_of(e.reinits.begin(), e.reinits.end(),
                    [](double v) { return !std::isnan(v); }))
      withReinit.push_back(&e);
  // Zeno: the events with a reinit come ever closer, geometrically (each
  // spacing shorter, at a mean ratio below 0.99), and either the rest of
  // the series ends within `span`, or the newest event breaks the series:
  // far closer than it predicts, or a reinit value of the other sign.
  // That is the solver's noise, the excursions between the events having
  // shrunk below its tolerances (the ball would fall through the floor).
  auto ratioOf = [&](size_t last) { // of the kZenoEvents ending at `last`
    if (last + 1 < kZenoEvents)
      return 1.0;
    double prev = std::numeric_limits<double>::infinity();
    for (size_t i = last + 2 - kZenoEvents; i <= last; ++i) {
      double d = withReinit[i]->t - withReinit[i - 1]->t;
      if (!(d < prev) || !(d > 0))
        return 1.0;
      prev = d;
    }
    double first = withReinit[last + 2 - kZenoEvents]->t -
                   withReinit[last + 1 - kZenoEvents]->t;
    double r = std::pow(prev / first, 1.0 / double(kZenoEvents - 2));
    return r < 0.99 ? r : 1.0;
  };
  bool reinitNow = std::any_of(fired.begin(), fired.end(),
                               [](double v) { return !std::isnan(v); });
  size_t n = reinitNow ? withReinit.size() : 0;
  bool zeno = false;
  size_t lastOfSeries = n - 1; // the newest event that belongs to it
  if (n > kZenoEvents) {
    double r = ratioOf(n - 2);
    if (r < 1) {
      double dPrev = withReinit[n - 2]->t - withReinit[n - 3]->t;
      double dNew = withReinit[n - 1]->t - withReinit[n - 2]->t;
      bool flipped = false;
      for (size_t k = 0; k < fired.size(); ++k) {
        double a = withReinit[n - 2]->reinits[k], b = fired[k];
        flipped |= !std::isnan(a) && !std::isnan(b) && a * b < 0;
      }
      if (flipped || dNew < dPrev * r / 4) {
        zeno = true;
        lastOfSeries = n - 2;
      }
    }
  }
  if (!zeno && n >= kZenoEvents && ratioOf(n - 1) < 1) {
    // The rest of the series ends within `span`; or its reinit values
    // have fallen below sqrt(rtol) of their largest: the excursions
    // between the events (a bounce's height ~ v^2) are at the level of
    // the tolerances, where the next crossing may go unseen.
    double r = ratioOf(n - 1);
    double dLast = withReinit[n - 1]->t - withReinit[n - 2]->t;
    bool small = true;
    for (size_t k = 0; k < fired.size(); ++k)
      if (!std::isnan(fired[k]))
        small &= std::fabs(fired[k]) <= std::sqrt(rtol_) * reinitScale_[k];
    zeno = dLast * r / (1 - r) < span || small;
  }
  // The reinit values tend to 0: each one that fired shrank over the
  // series.
  bool vanishing = zeno;
  if (zeno) {
    const Recent &a = *withReinit[lastOfSeries + 1 - kZenoEvents],
                 &b = *withReinit[lastOfSeries];
    for (size_t k = 0; k < fired.size(); ++k)
      if (!std::isnan(b.reinits[k]))
        vanishing &= !std::isnan(a.reinits[k]) &&
                     std::fabs(b.reinits[k]) < std::fabs(a.reinits[k]);
  }
  bool chatter = recent_.size() > kChatterEvents &&
                 t - recent_.front().t < kChatterSpan * (1 + std::fabs(t));
  if (!zeno && !chatter)
    return EventOutcome::Handled;
  std::vector<bool> which(nd_, false);
  for (const Recent &e : recent_)
    for (int k = 0; k < nd_; ++k)
      if (e.changed[k] &&
          (!m_.discrete_kind || m_.discrete_kind[k] == LDAE_DISCRETE_RELATION ||
           m_.discrete_kind[k] == LDAE_DISCRETE_WHEN))
        which[k] = true;
  if (std::none_of(which.begin(), which.end(), [](bool b) { return b; }))
    for (const Recent &e : recent_)
      for (int k = 0; k < nd_; ++k)
        which[k] = which[k] || e.changed[k];
  double spanSeen = t - recent_.front().t;
  if (zeno && vanishing) {
    std::string targets;
    for (size_t r = 0; r < fired.size(); ++r)
      if (reinitScale_[r] > 0) {
        int i = m_.reinit_target[r];
        targets += (targets.empty() ? "'" : ", '") + ev_.varName(i) + "'";
        y[i] = 0; // the limit of the values the reinits assign
      }
    message_ = fmt::format(
        "t = {:.10g}: events accumulate (Zeno): {} events in {:.3g} s on {}, "
        "spaced ever closer, and the reinit values ({}) tend to 0: past the "
        "accumulation point the state is held at rest",
        t, recent_.size(), spanSeen, namesOf(which), targets);
    return EventOutcome::AtRest;
  }
  message_ = fmt::format("chattering at t = {:.10g}: {} events within {:.3g} "
                         "s; the conditions that keep changing: {}",
                         t, recent_.size(), spanSeen, namesOf(which));
  return EventOutcome::Failed;
}

void EventLoop::prime(double t, const double *y, const double *yp) {
  if (!active() || !m_.discrete_kind)
    return;
  std::vector<double> kept(ev_.discrete(), ev_.discrete() + nd_);
  setKind(LDAE_DISCRETE_INITIAL, 1.0);
  // A failure shows again at the initial event, which reports it.
  bool ok = update(t, y, yp);
  std::copy(kept.begin(), kept.end(), ev_.discrete());
  if (ok)
    for (int k = 0; k < nd_; ++k)
      if (m_.discrete_kind[k] == LDAE_DISCRETE_VARIABLE)
        ev_.discrete()[k] = out_[k];
}

void EventLoop::settle(int kind, double t, const double *y, const double *yp) {
  setKind(kind, 0.0);
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  if (update(t, y, yp))
    std::copy(out_.begin(), out_.begin() + nd_, ev_.discrete());
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
}

void EventLoop::recordDelays(double t, const double *y, const double *yp) {
  if (delays_.empty())
    return;
  std::vector<double> te = timeEventValues(t, y, yp);
  if (!te.empty())
    delays_.record(t, te.data());
}

EventOutcome EventLoop::initial(double t, std::vector<double> &y,
                                std::vector<double> &yp,
                                const Reinitialize &reinit) {
  if (!active())
    return EventOutcome::Unchanged;
  setKind(LDAE_DISCRETE_INITIAL, 1.0);
  for (int s = 0; s < m_.n_samples; ++s)
    if (sampleInstant(s, t, y.data(), yp.data()))
      ev_.discrete()[m_.sample_discrete[s]] = 1.0;
  EventOutcome out = iterate(t, y, yp, reinit);
  // The initial event is not counted among the events.
  if (out == EventOutcome::Handled && !recent_.empty())
    recent_.pop_back();
  if (out == EventOutcome::Failed || out == EventOutcome::ModeChange ||
      out == EventOutcome::Terminated)
    return out;
  if (!delays_.empty()) {
    std::vector<double> te = timeEventValues(t, y.data(), yp.data());
    if (te.empty() || !delays_.start(t, te.data(), ev_.discrete(), message_)) {
      if (te.empty())
        message_ = fmt::format("t = {:.10g}: the delay times could not be "
                               "evaluated", t);
      return EventOutcome::Failed;
    }
  }
  // Initialization is over: what its values set off (`x = pre(v)` moving
  // as pre(v) := v, `change(x) and not initial()`, `not initial()`)
  // happens in the event iteration at the start time, as Dymola runs
  // MSL's Digital gates.
  setKind(LDAE_DISCRETE_SAMPLE, 0.0);
  setKind(LDAE_DISCRETE_INITIAL, 0.0);
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  EventOutcome after = iterate(t, y, yp, reinit);
  if (after == EventOutcome::Handled && !recent_.empty())
    recent_.pop_back();
  if (after != EventOutcome::Failed && after != EventOutcome::ModeChange)
    recordDelays(t, y.data(), yp.data());
  if (after == EventOutcome::Unchanged ||
      (after == EventOutcome::Restarted && out != EventOutcome::Unchanged))
    return out;
  return after;
}

EventOutcome EventLoop::handle(double t, std::vector<double> &y,
                               std::vector<double> &yp, bool timeEvent,
                               const Reinitialize &reinit) {
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  bool sampled = false;
  // A delayed value due now is an input of this event, as a sample is.
  if (timeEvent)
    delays_.release(t, ev_.discrete());
  if (timeEvent)
    for (int s = 0; s < m_.n_samples; ++s)
      if (sampleInstant(s, t, y.data(), yp.data())) {
        ev_.discrete()[m_.sample_discrete[s]] = 1.0;
        sampled = true;
      }
  EventOutcome out = iterate(t, y, yp, reinit);
  if (sampled && out != EventOutcome::Failed &&
      out != EventOutcome::ModeChange) {
    std::vector<double> was(ev_.discrete(), ev_.discrete() + nd_);
    settle(LDAE_DISCRETE_SAMPLE, t, y.data(), yp.data());
    bool moved = false;
    for (int k = 0; k < nd_; ++k)
      moved |= m_.discrete_kind[k] != LDAE_DISCRETE_SAMPLE &&
               differs(was[k], ev_.discrete()[k]);
    std::string failure;
    if (moved && !reinit(t, y, yp, {}, failure)) {
      message_ = failure;
      return EventOutcome::Failed;
    }
  }
  if (out != EventOutcome::Unchanged && out != EventOutcome::Restarted) {
    ++events_;
    timeEvents_ += timeEvent;
  }
  if (out != EventOutcome::Failed && out != EventOutcome::ModeChange)
    recordDelays(t, y.data(), yp.data());
  return out;
}

EventOutcome EventLoop::resume(double t, std::vector<double> &y,
                               std::vector<double> &yp,
                               const Reinitialize &reinit) {
  // Each mode's model has its own event loop: the history of e would
  // stay behind in the old one.
  if (!delays_.empty()) {
    message_ = fmt::format("t = {:.10g}: the structure changed in a model "
                           "with delay(), whose history does not carry "
                           "over to the new mode: not supported",
                           t);
    return EventOutcome::Failed;
  }
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  EventOutcome out = iterate(t, y, yp, reinit);
  // Counted in the old mode already.
  return out == EventOutcome::Unchanged || out == EventOutcome::Restarted
             ? EventOutcome::Handled
             : out;
}

EventOutcome EventLoop::comeToRest(double t, std::vector<double> &y,
                                   std::vector<double> &yp) {
  if (!active())
    return EventOutcome::Unchanged;
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  recent_.clear();
  // The point is held: nothing to re-initialize (a fired reinit writes its
  // value, which is the limit the series tends to).
  Reinitialize held = [](double, std::vector<double> &, std::vector<double> &,
                         const std::vector<int> &,
                         std::string &) { return true; };
  EventOutcome out = iterate(t, y, yp, held);
  recent_.clear();
  return out;
}

bool EventLoop::terminal(double t, const double *y, const double *yp) {
  if (!active())
    return false;
  std::copy(ev_.discrete(), ev_.discrete() + nd_, ev_.pre());
  setKind(LDAE_DISCRETE_TERMINAL, 1.0);
  if (!update(t, y, yp))
    return false;
  bool changed = false;
  for (int k = 0; k < nd_; ++k) {
    changed |= m_.discrete_kind[k] != LDAE_DISCRETE_TERMINAL &&
               differs(out_[k], ev_.discrete()[k]);
    ev_.discrete()[k] = out_[k];
  }
  return changed;
}

} // namespace ldae::runtime
