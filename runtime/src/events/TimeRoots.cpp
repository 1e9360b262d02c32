// Zero crossings of a model without unknowns (see TimeRoots.h).
#include "events/TimeRoots.h"

#include <algorithm>
#include <cmath>

namespace ldae::runtime {

namespace {
/// Sub-steps per stretch: a relation that turns true and false again
/// within one sub-step goes unseen, as it does within one integrator step
/// of a model with unknowns (whose steps are capped at the output
/// interval).
constexpr int kSubSteps = 16;

int signOf(double v) { return (v > 0) - (v < 0); }
} // namespace

TimeRoots::TimeRoots(const ModelEval &ev)
    : ev_(ev), nr_(std::max(ev.model().n_roots, 0)) {}

bool TimeRoots::evaluate(double t, std::vector<double> &g) const {
  const ldae_model &m = ev_.model();
  g.assign(nr_, 0.0);
  const double none = 0;
  return nr_ > 0 && m.roots &&
         m.roots(t, &none, &none, ev_.params(), g.data()) == 0;
}

bool TimeRoots::signChanged(const std::vector<double> &a,
                            const std::vector<double> &g) {
  for (size_t j = 0; j < a.size(); ++j)
    if (signOf(a[j]) != signOf(g[j]))
      return true;
  return false;
}

double TimeRoots::first(double from, double to) {
  std::vector<double> g0, g;
  if (!(to > from) || !evaluate(from, g0))
    return to;
  double lo = from;
  for (int k = 1; k <= kSubSteps; ++k) {
    double hi = k == kSubSteps ? to : from + (to - from) * k / kSubSteps;
    if (!evaluate(hi, g) || !signChanged(g0, g)) {
      lo = hi;
      continue;
    }
    // Bisect to a few ulps of time (as a root the integrator returns is
    // moved past): the crossing lies in (lo, hi].
    while (hi - lo > 4e-16 * std::max(1.0, std::fabs(hi))) {
      double mid = lo + (hi - lo) / 2;
      if (mid <= lo || mid >= hi)
        break;
      if (evaluate(mid, g) && signChanged(g0, g))
        hi = mid;
      else
        lo = mid;
    }
    return hi;
  }
  return to;
}

} // namespace ldae::runtime
