// Dynamic state selection: which of the model's state sets to integrate
// with, judged by the conditioning of each set's pivot matrix (the block of
// the differentiated constraints' Jacobian at the dummy derivatives).
//
// The rule (docs/runtime.md): with s_max = the largest singular value over
// all sets' pivot matrices at the current point, the set k's condition is
// cond_k = s_max / sigma_min(M_k) (infinite if M_k is singular). Scaling by
// the largest pivot of any set, not M_k's own, keeps the measure meaningful
// for 1 x 1 pivots. Switch from the current set c to the best set b when
//   cond_c > kSwitchThreshold  and  cond_b * kHysteresis < cond_c,
// so a set is left only when it is clearly bad and another is clearly
// better, and the run does not flip back and forth at the boundary.
#pragma once

#include "ModelEval.h"

#include <vector>

namespace ldae::runtime {

/// A set's condition above this may trigger a switch.
inline constexpr double kSwitchThreshold = 4.0;
/// How much better (factor) the new set must be.
inline constexpr double kHysteresis = 2.0;

/// cond_k for every set (infinity for a set whose pivot cannot be
/// evaluated or is singular; 1 for sets with no pivot).
std::vector<double> pivotConditions(const ModelEval &ev, double t,
                                    const double *y, const double *yp);

/// The set to continue with: `current`, or a better one by the rule above.
int chooseStateSet(const std::vector<double> &cond, int current);

} // namespace ldae::runtime
