// Tells the zero crossings of relations from round-off (docs/events.md,
// "Crossings within round-off"). At an ideal diode's switching point the
// new mode's relation reads a value that is zero to its second order
// (v = vs - vc leaves 0 with zero slope) and its sign is round-off for a
// while: the root finder would report crossings of 1e-20 V back and forth.
// A crossing counts only after the root function has been away from zero by
// more than a floor (kFloor times the largest |g| of that root seen in the
// run) since the last event; a crossing ignored that way is made up for when
// the root function leaves the floor on the other side (an event forced at
// that step), so that no real change of sign is lost.
//
// A root function exactly zero at a start or restart (`when x > 0` with
// x(0) = 0 and der(x) = 1) is set aside by IDA and CVODE until it leaves
// zero, and its leaving is reported as no root: the relation's change just
// after the start would be missed. So such a root function is watched here
// too, the first step after the restart is made short (aheadOfZero), and
// when it has left zero an event is due at that step (the event iteration
// finds whether the relation changed).
#pragma once

#include "model/ModelEval.h"

#include <cstddef>
#include <vector>

namespace ldae::runtime {

class RootWatch {
public:
  explicit RootWatch(const ModelEval &ev);

  /// After a step to (t, y, y'): whether an ignored crossing turned out to
  /// be real (the root function beyond the floor on the other side of the
  /// last event's): an event is due at t.
  bool stepped(double t, const double *y, const double *yp);
  /// At a root return: whether every root found (`found`, the integrator's
  /// root info) is a crossing within round-off, to be ignored.
  bool withinRoundOff(const std::vector<int> &found);
  /// After an event or a restart at (t, y, y'): the excursions start again.
  void restarted(double t, const double *y, const double *yp);
  /// Where the integrator should stop first after a restart at t: just
  /// after t (far past round-off of t, far below any tolerance on it) when
  /// a root function was exactly zero there, so that its leaving zero is
  /// located there; +infinity otherwise, and after the first call since
  /// the restart (a root function that stays zero must not hold every
  /// step to that length).
  double stopAheadOfZero(double t);
  /// At an event at t the roots `found` caused, which assigned no reinit and
  /// made no jump (call before restarted()): counts, per root, the events
  /// in a row since each of which its function stayed within kSlidingBand
  /// of its largest magnitude in the run. Returns a root that reached
  /// `events` such events in a row within `span` seconds, or -1: the state
  /// chatters along that root's surface, where the vector fields of both
  /// sides point at it (a Filippov sliding mode), at whatever rate the
  /// steps allow. (Both tests are needed: a comparator's function swings
  /// across its range between switchings however fast they come, and a
  /// decaying oscillation's crossings come slowly however small it gets.)
  int sliding(double t, const std::vector<int> &found, size_t events,
              double span);
  /// The time of the first event of the run of events that sliding()
  /// counted for root j.
  double slidingSince(int j) const { return slideSince_[j]; }

private:
  bool evaluate(double t, const double *y, const double *yp);

  const ModelEval &ev_;
  int nr_;
  std::vector<double> g_, scale_, excursion_, atRestart_;
  std::vector<size_t> slideEvents_; // sliding(): events in a row near zero
  std::vector<double> slideSince_;
  std::vector<bool> pending_; // a crossing was ignored since the restart
  std::vector<bool> zero_;    // exactly zero at the restart, not left yet
  bool aimedAhead_ = false;   // stopAheadOfZero answered since the restart
};

} // namespace ldae::runtime
