// Values within round-off of zero are zero (docs/events.md, "Zeros within
// round-off"): the point an event iteration reads is a numerical solution,
// and a value that is exactly 0 in the model (the speed of a stuck friction
// element, the torque on the idle side of a locked gear) comes out of the
// dense Newton steps of the (re-)initialization as +-1e-30 or so. A
// relation `v > 0` or `tau >= 0` would read the sign of that round-off, and
// a discrete value that decides the equations (MSL's `initial() and v > 0`
// starting a friction element forward) would flip with it from one solve
// to the next: an event iteration that never settles.
#pragma once

#include "model/ModelEval.h"

#include <vector>

namespace ldae::runtime {

/// A value at most this times its unknown's nominal value is round-off
/// of 0: the last Newton step of a converged solve is far below it, and
/// the integrator's error test (atol scaled by the nominal) cannot tell
/// such a value from 0 anyway.
inline constexpr double kRoundOffZero = 2.220446049250313e-16; // DBL_EPSILON

/// Sets to exactly 0 the entries of y and y' within round-off of 0 (each
/// scaled by its unknown's nominal value) that a solve moved there from
/// (yFrom, ypFrom), the point it started from. The values it left as they
/// were are the integrator's (a bouncing ball's h = -1e-16 at the bounce,
/// within its tolerances): they stay. True when one changed.
bool snapRoundOffZeros(const ModelEval &ev, std::vector<double> &y,
                       std::vector<double> &yp, const double *yFrom,
                       const double *ypFrom);

} // namespace ldae::runtime
