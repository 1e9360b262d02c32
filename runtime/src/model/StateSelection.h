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
//
// Blocks too large to enumerate (ldae_model::dynamic_sets) are chosen the
// same way between two candidates: the current dummies and the ones a
// column-pivoted factorization of the block's Jacobian picks now
// (numeric/StatePivot.h), each measured by dummyCondition. A switch
// rewrites the selection matrix A in p and sets the block's states and
// their derivatives to A c and A der(c), so the point stays consistent.
#pragma once

#include "model/ModelEval.h"

#include <string>
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

/// One dynamic set switched by reselectDynamicSets.
struct DynamicSwitch {
  int set = 0;
  std::string from, to; // the states' names
  double condFrom = 0, condTo = 0;
};

/// Re-chooses the states of every dynamic set at (t, y, y') by the rule
/// above; where one switches, writes its A into ev's p and its states and
/// their derivatives into y and yp. Returns what switched (empty: nothing;
/// a set whose Jacobian cannot be evaluated keeps its states).
std::vector<DynamicSwitch> reselectDynamicSets(ModelEval &ev, double t,
                                               double *y, double *yp);

} // namespace ldae::runtime
