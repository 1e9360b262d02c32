// The discrete side of a run (docs/events.md): time events, the event
// iteration at the initial event, at roots and at time events, the terminal
// event, chattering and Zeno detection, and the counters of --stats. It
// changes the discrete values inside ModelEval's parameter vector, which
// every ABI function (and so the integrator's callbacks) reads; the
// continuous point is re-initialized through a hook the run loop gives
// (Simulator.cpp owns the integrator and the initialization).
#pragma once

#include "events/DelayLine.h"
#include "model/ModelEval.h"

#include <deque>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace ldae::runtime {

/// Makes (t, y, y') consistent with the current discrete values and
/// restarts the integrator there; `held` are the unknowns whose values are
/// conditions of the re-initialization (the targets of fired reinits).
/// Returns false with the failure written into `failure`.
using Reinitialize = std::function<bool(
    double t, std::vector<double> &y, std::vector<double> &yp,
    const std::vector<int> &held, std::string &failure)>;

/// What an event ended in.
enum class EventOutcome {
  Unchanged,  ///< a root that changes nothing: no event, no restart
  Restarted,  ///< the iteration came back to the discrete values it
              ///< started from: no event, but the integrator restarted
  Handled,    ///< discrete values changed; the integrator was restarted
  Terminated, ///< terminate() fired: the run ends here (status 0)
  ModeChange, ///< a mode value changed: the run needs another model
  AtRest,     ///< Zeno with vanishing reinit values: held at rest
  Failed      ///< see message()
};

/// Chattering: more than this many events ...
inline constexpr size_t kChatterEvents = 50;
/// ... within this span relative to 1 + |t|. Not 1e-9: a condition that
/// switches itself back is seen again only after the integrator's first
/// step from the restart (crossings within round-off do not count,
/// RootWatch.h), some 1e-10 s. The same rule holds for mode switches,
/// each a run of its own mode's model (Simulator.cpp).
inline constexpr double kChatterSpan = 1e-6;

class EventLoop {
public:
  /// `rtol`: the run's relative tolerance (the scale below which a series
  /// of events is the solver's noise); `log` may be null.
  EventLoop(ModelEval &ev, double rtol, std::ostream *log);

  /// Whether the model has a discrete state at all.
  bool active() const { return nd_ > 0; }
  /// Whether root j is a relation's zero crossing handled here.
  bool handlesRoots() const { return active() && m_.root_relation; }

  /// Whether a sample has an instant at t: at the start time, the event
  /// right after the initial event (where only when-clauses with initial()
  /// fired), as OpenModelica and Dymola run it.
  bool sampleInstantAt(double t, const double *y, const double *yp) const;
  /// The first time event strictly after t, or +infinity.
  double nextTimeEvent(double t, const double *y, const double *yp) const;

  /// Before the initialization at `t` from the start point (y, y'): the
  /// discrete variables take the update's values there with initial()
  /// true (their pre() values stay the start values). Their equations are
  /// equations of the initialization (MLS 8.6, a when-clause that fires at
  /// initial() too), solved before the equations that read them: an MSL
  /// table's output reads its next event time, and read before its
  /// getNextTimeEvent ran, its C code indexed an interval table not yet
  /// built (IntegerTable crashed). What reads unknowns reads their start
  /// values here; the initial event evaluates it again on the initialized
  /// point.
  void prime(double t, const double *y, const double *yp);
  /// The initial event at `t` (initial() = 1): the initialization's
  /// discrete values from the start values, then initial() = 0 and the
  /// event iteration at t (pre(v) := v; a when-clause whose condition
  /// becomes true there fires). (y, y') in: the initialized point;
  /// out: the point after the event (the integrator restarted there when
  /// it moved).
  EventOutcome initial(double t, std::vector<double> &y,
                       std::vector<double> &yp, const Reinitialize &reinit);
  /// An event at t (a root, or a time event when `timeEvent`).
  EventOutcome handle(double t, std::vector<double> &y, std::vector<double> &yp,
                      bool timeEvent, const Reinitialize &reinit);
  /// Goes on with an event iteration that a mode change interrupted, in
  /// the new mode's model (its discrete values carried over).
  EventOutcome resume(double t, std::vector<double> &y, std::vector<double> &yp,
                      const Reinitialize &reinit);
  /// After AtRest: the event iteration at the state held at rest (the
  /// reinit targets at their limit 0, y' = 0), so that the discrete values
  /// the model computes from it follow (a `flying` flag false, a
  /// `v_new` 0); no accumulation is looked for. Failed (with the message)
  /// when it does not settle.
  EventOutcome comeToRest(double t, std::vector<double> &y,
                          std::vector<double> &yp);
  /// The terminal event at the end of the run (terminal() = 1, one update).
  /// True when it changed a discrete value.
  bool terminal(double t, const double *y, const double *yp);

  /// The state set the integrator runs: its differential flags tell jumps,
  /// and the right limit of a mode change solves its algebraic unknowns.
  void setStateSet(int set) {
    set_ = set;
    states_ = ev_.set(set).is_differential;
  }
  /// Counts a jump and logs the states that moved from `before` to
  /// `after` (beyond round-off), if any.
  void noteJump(double t, const std::vector<double> &before,
                const std::vector<double> &after);

  /// The discrete values of the mode (ldae_model::mode_discrete order).
  std::vector<double> modeValues() const;
  /// The message of Terminated, AtRest and Failed.
  const std::string &message() const { return message_; }

  long events() const { return events_; }
  long timeEvents() const { return timeEvents_; }
  long jumps() const { return jumps_; }

private:
  bool update(double t, const double *y, const double *yp);
  EventOutcome iterate(double t, std::vector<double> &y,
                       std::vector<double> &yp, const Reinitialize &reinit);
  /// Whether the residuals or the outputs at (t, y, y') read the discrete
  /// values the last update changed: they differ from `readBefore`, what
  /// they read before that update ran (readings()).
  bool observed(double t, const std::vector<double> &y,
                const std::vector<double> &yp,
                const std::vector<double> &readBefore);
  /// The residuals of every state set (and the outputs, with `outputs`) at
  /// (t, y, y') with the nd_ values at `slots` (the discrete values or
  /// their pre() values) replaced by `with` (none: as they are); empty if
  /// they could not be evaluated.
  std::vector<double> readings(double t, const std::vector<double> &y,
                               const std::vector<double> &yp, double *slots,
                               const double *with, bool outputs);
  /// Whether the residuals (and the outputs, with `outputs`) at (t, y, y')
  /// change when the nd_ values at `slots` are replaced by `against`.
  bool reads(double t, const std::vector<double> &y,
             const std::vector<double> &yp, double *slots,
             const double *against, bool outputs);
  /// Whether one of `contradicted` from index `from` on (each a solved
  /// point's discrete values, which the update at that point changed)
  /// equals the current values: the iteration came back to it.
  bool contradictedNow(const std::vector<std::vector<double>> &contradicted,
                       size_t from) const;
  /// Whether the update at (t, y, y') gives the current discrete values
  /// back.
  bool reproduces(double t, const std::vector<double> &y,
                  const std::vector<double> &yp);
  /// Whether only relations are among the `changed` values.
  bool onlyRelations(const std::vector<bool> &changed) const;
  void settle(int kind, double t, const double *y, const double *yp);
  void setKind(int kind, double v);
  bool sampleInstant(int s, double t, const double *y, const double *yp) const;
  /// time_events' output at t (empty when it fails or there is none).
  std::vector<double> timeEventValues(double t, const double *y,
                                      const double *yp) const;
  /// After an event settled at t: delay() lines take e's new values.
  void recordDelays(double t, const double *y, const double *yp);
  EventOutcome checkAccumulation(double t, std::vector<double> &y,
                                 const std::vector<double> &fired);
  bool modeChanged() const;
  std::string namesOf(const std::vector<bool> &which) const;

  ModelEval &ev_;
  const ldae_model &m_;
  int nd_;
  double rtol_;
  std::ostream *log_;
  int set_ = 0;
  const int *states_ = nullptr; // of set_; null before setStateSet
  std::vector<double> out_; // event_update's output
  DelayLines delays_;
  std::string message_;
  long events_ = 0, timeEvents_ = 0, jumps_ = 0;

  /// Recent events, for chattering and Zeno detection.
  struct Recent {
    double t;
    std::vector<bool> changed;   // discrete values changed by it
    std::vector<double> reinits; // |value| of each reinit that fired (NaN: not)
  };
  std::deque<Recent> recent_;
  std::vector<double> reinitScale_; // the largest |value| of each reinit seen
};

} // namespace ldae::runtime
