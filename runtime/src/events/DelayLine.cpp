// The delay lines of delay() (see DelayLine.h and docs/events.md).
#include "events/DelayLine.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace ldae::runtime {

namespace {

/// The instants are sums t_event + d, computed once and compared with the
/// time the run stopped at, which is that same double; the slack only
/// absorbs a stop time the integrator rounded.
bool dueBy(double instant, double t) {
  return instant <= t + 4e-16 * std::max(1.0, std::fabs(t));
}

} // namespace

DelayLines::DelayLines(const ldae_model &m) : m_(m) {
  int nth = std::max(m.n_time_thresholds, 0), ns = std::max(m.n_samples, 0);
  int offset = nth + 2 * ns;
  for (int k = 0; m.discrete_kind && k < m.n_discrete; ++k)
    if (m.discrete_kind[k] == LDAE_DISCRETE_DELAY) {
      Line l;
      l.slot = k;
      l.offset = offset;
      offset += 3;
      lines_.push_back(l);
    }
}

bool DelayLines::start(double t, const double *te, const double *discrete,
                       std::string &failure) {
  for (Line &l : lines_) {
    double d = te[l.offset + 1], max = te[l.offset + 2];
    const char *name = m_.discrete_names[l.slot];
    if (!(d >= 0) || !std::isfinite(d)) {
      failure = fmt::format("t = {:.10g}: the delay time of {} is {:.10g}; "
                            "it must be at least 0",
                            t, name, d);
      return false;
    }
    if (d > max) {
      failure = fmt::format("t = {:.10g}: the delay time of {} is {:.10g}, "
                            "above its maximum delay {:.10g}",
                            t, name, d, max);
      return false;
    }
    l.d = d;
    l.last = discrete[l.slot];
    l.due.clear();
  }
  return true;
}

bool DelayLines::differs(const Line &l, double v) {
  return l.d > 0 && v != l.last && !(std::isnan(v) && std::isnan(l.last));
}

void DelayLines::record(double t, const double *te) {
  for (Line &l : lines_) {
    double v = te[l.offset];
    if (!differs(l, v))
      continue;
    // A value that replaces one due at the same instant (several events
    // at one time) keeps only the last.
    if (!l.due.empty() && l.due.back().first == t + l.d)
      l.due.back().second = v;
    else
      l.due.emplace_back(t + l.d, v);
    l.last = v;
  }
}

bool DelayLines::moved(const double *te) const {
  for (const Line &l : lines_) {
    double v = te[l.offset];
    if (differs(l, v))
      return true;
  }
  return false;
}

double DelayLines::next(double t) const {
  double next = std::numeric_limits<double>::infinity();
  for (const Line &l : lines_)
    for (const auto &[instant, value] : l.due)
      if (instant > t) {
        next = std::min(next, instant);
        break;
      }
  return next;
}

bool DelayLines::release(double t, double *discrete) {
  bool any = false;
  for (Line &l : lines_)
    while (!l.due.empty() && dueBy(l.due.front().first, t)) {
      discrete[l.slot] = l.due.front().second;
      l.due.pop_front();
      any = true;
    }
  return any;
}

} // namespace ldae::runtime
