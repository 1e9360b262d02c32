// The message a user sees when IDA gives up: the time, what failed, the
// variables with the largest weighted local error, the equation behind it
// (the row of a domain error, or the rows a singular iteration matrix
// singles out), and a hint at what to try.
#pragma once

#include "IdaIntegrator.h"

#include <string>

namespace ldae::runtime {

/// Our own failure code (beside IDA's): the step size collapsed to
/// round-off level while IDA kept succeeding (e.g. creeping towards a
/// domain boundary).
inline constexpr int kStepCollapsed = -1000;

/// Describes the failure of IDASolve with `flag` (< 0) at time `t`.
std::string describeFailure(const ModelEval &ev, const IdaIntegrator &ida,
                            int flag, double t);

/// Describes a failed IDACalcIC (`flag` < 0) at the start time `t`.
std::string describeInitFailure(const ModelEval &ev, const IdaIntegrator &ida,
                                int flag, double t);

} // namespace ldae::runtime
