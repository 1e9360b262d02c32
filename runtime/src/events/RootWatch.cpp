// Crossings within round-off (see RootWatch.h).
#include "events/RootWatch.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldae::runtime {

namespace {
/// The floor relative to the root function's largest magnitude in the run:
/// far above round-off of values of that size (1e-16), far below what any
/// tolerance resolves.
constexpr double kFloor = 1e-13;
/// A root function that stays within this fraction of its largest
/// magnitude between events is on its surface: a relay's or a comparator's
/// function swings across its range between switchings, a sliding one
/// stays at the step size times its rate (Tiller's chatter model: 2e-5 of
/// 1).
constexpr double kSlidingBand = 1e-3;
} // namespace

RootWatch::RootWatch(const ModelEval &ev)
    : ev_(ev), nr_(std::max(ev.model().n_roots, 0)), g_(nr_), scale_(nr_, 0.0),
      excursion_(nr_, 0.0), atRestart_(nr_, 0.0), slideEvents_(nr_, 0),
      slideSince_(nr_, 0.0), pending_(nr_, false), zero_(nr_, false) {}

bool RootWatch::evaluate(double t, const double *y, const double *yp) {
  const ldae_model &m = ev_.model();
  if (nr_ == 0 || !m.roots || m.roots(t, y, yp, ev_.params(), g_.data()) != 0)
    return false;
  for (int j = 0; j < nr_; ++j) {
    scale_[j] = std::max(scale_[j], std::fabs(g_[j]));
    excursion_[j] = std::max(excursion_[j], std::fabs(g_[j]));
  }
  return true;
}

int RootWatch::sliding(double t, const std::vector<int> &found,
                       size_t events, double span) {
  for (int j = 0; j < nr_ && j < int(found.size()); ++j) {
    if (!found[j])
      continue;
    bool near = scale_[j] > 0 && excursion_[j] <= kSlidingBand * scale_[j];
    // A run of near events that takes longer than `span` starts again
    // from this one.
    if (!near || (slideEvents_[j] > 0 && t - slideSince_[j] > span))
      slideEvents_[j] = 0;
    if (near && slideEvents_[j]++ == 0)
      slideSince_[j] = t;
    if (slideEvents_[j] >= events)
      return j;
  }
  return -1;
}

void RootWatch::restarted(double t, const double *y, const double *yp) {
  std::fill(excursion_.begin(), excursion_.end(), 0.0);
  std::fill(pending_.begin(), pending_.end(), false);
  std::fill(zero_.begin(), zero_.end(), false);
  aimedAhead_ = false;
  if (!evaluate(t, y, yp))
    return;
  atRestart_ = g_;
  for (int j = 0; j < nr_; ++j)
    zero_[j] = g_[j] == 0;
}

double RootWatch::stopAheadOfZero(double t) {
  bool any = std::find(zero_.begin(), zero_.end(), true) != zero_.end();
  if (aimedAhead_ || !any)
    return std::numeric_limits<double>::infinity();
  aimedAhead_ = true;
  return t + 1.4901161193847656e-08 * (1.0 + std::fabs(t)); // sqrt(eps)
}

bool RootWatch::stepped(double t, const double *y, const double *yp) {
  auto none = [](const std::vector<bool> &v) {
    return std::find(v.begin(), v.end(), true) == v.end();
  };
  if (none(pending_) && none(zero_))
    return evaluate(t, y, yp) && false;
  if (!evaluate(t, y, yp))
    return false;
  bool due = false;
  for (int j = 0; j < nr_; ++j) {
    if ((!pending_[j] && !zero_[j]) || std::fabs(g_[j]) <= kFloor * scale_[j])
      continue;
    // Left zero: whether the relation changed is the event's to find.
    due |= zero_[j];
    zero_[j] = false;
    if (!pending_[j])
      continue;
    pending_[j] = false;
    // Back on the side it started from: the crossings were round-off.
    due |= !(g_[j] * atRestart_[j] > 0);
  }
  return due;
}

bool RootWatch::withinRoundOff(const std::vector<int> &found) {
  bool all = true, any = false;
  for (int j = 0; j < nr_ && j < int(found.size()); ++j) {
    if (found[j] == 0)
      continue;
    any = true;
    if (excursion_[j] > kFloor * scale_[j] || scale_[j] == 0)
      all = false;
  }
  if (!any || !all)
    return false;
  for (int j = 0; j < nr_ && j < int(found.size()); ++j)
    if (found[j] != 0)
      pending_[j] = true;
  return true;
}

} // namespace ldae::runtime
