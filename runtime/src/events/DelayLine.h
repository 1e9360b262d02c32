// delay(e, d) of an e that changes at events only (docs/events.md,
// "delay()"): the values e took after each event, each due d later. The
// delayed value is a discrete value of kind LDAE_DISCRETE_DELAY that jumps
// at those instants, time events the run hits exactly; between them it
// holds. The time_events function gives e's current value, d and the
// maximum delay after the thresholds and samples.
#pragma once

#include "ldae/model.h"

#include <deque>
#include <string>
#include <vector>

namespace ldae::runtime {

class DelayLines {
public:
  explicit DelayLines(const ldae_model &m);

  bool empty() const { return lines_.empty(); }
  size_t size() const { return lines_.size(); }

  /// The start, after the initialization's rounds of the initial event:
  /// checks 0 <= d <= max of each delay (false with the message) and
  /// keeps the current delayed values, e's at the start, as the history
  /// before it. `te`: time_events' output at t; `discrete`: the current
  /// discrete values.
  bool start(double t, const double *te, const double *discrete,
             std::string &failure);
  /// After an event at t settled: each e whose value changed is due,
  /// with its new value, at t + d.
  void record(double t, const double *te);
  /// Whether some e has a value other than the one recorded last.
  bool moved(const double *te) const;
  /// The first instant a delayed value is due strictly after t, or
  /// +infinity.
  double next(double t) const;
  /// A time event at t: writes the values due at t into `discrete`; true
  /// when there were any.
  bool release(double t, double *discrete);

private:
  struct Line {
    int slot = 0;    // the delayed value's discrete index
    int offset = 0;  // of e's value in time_events' output; d, max follow
    double d = 0;    // the delay time, constant over the run
    double last = 0; // e's value recorded last
    std::deque<std::pair<double, double>> due; // (instant, value), by time
  };
  /// Whether e's value v is one to queue: it moved, and d > 0 (with
  /// d = 0 the update gives e itself, nothing is due later).
  static bool differs(const Line &l, double v);

  const ldae_model &m_;
  std::vector<Line> lines_;
};

} // namespace ldae::runtime
