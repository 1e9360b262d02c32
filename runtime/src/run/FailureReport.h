// The message a user sees when the integrator gives up: the time, what failed, the
// variables with the largest weighted local error, the equation behind it
// (the row of a domain error, or the rows a singular iteration matrix
// singles out), and a hint at what to try.
#pragma once

#include "integrators/Integrator.h"

#include <string>

namespace ldae::runtime {

/// The report of a domain error (sqrt or log of a negative number...) in
/// residual row `row` of state set `set` at the unknowns `y` (may be null):
/// the equation's location (file:line:col), its source line with a caret,
/// and the values of the unknowns it reads, each on a line of its own
/// starting with "\n  ". Where the failing operation is in a variable that
/// causalization computes inside the residual, that variable's equation is
/// named too (evaluated at `t`, `y`, `yp`; `yp` may be null: zeros). The
/// one form for initialization and the run.
std::string describeDomainRow(const ModelEval &ev, int set, int row,
                              const double *y, double t, const double *yp);

/// The whole message of a domain error met while initializing at `t`.
std::string describeInitDomainError(const ModelEval &ev, int set, int row,
                                    const double *y, double t);
/// The same met re-initializing after an event at `t`: the new discrete
/// values make an equation undefined (an ideal diode with Ron = 0 that
/// turns on divides by its resistance).
std::string describeEventDomainError(const ModelEval &ev, int set, int row,
                                     const double *y, double t);

/// The report of a domain error met computing output `output` at `t` (the
/// integration itself went on): the output, its equation's location and
/// source line, and `lastGood`, the last output time it was computed at.
std::string describeOutputDomainError(const ModelEval &ev, int output,
                                      double t, double lastGood,
                                      const double *y);

/// Describes a SUNDIALS set-up call that failed at time `t` with
/// `what` (e.g. a re-initialization after a state switch): a numerical failure of
/// the run like the others, with the time and a hint.
std::string describeSolverError(double t, const std::string &what);

/// Describes a failed step (`status`) at time `t`.
std::string describeFailure(const ModelEval &ev, const Integrator &integrator,
                            const StepStatus &status, double t);

/// Describes a failed start completion (IDACalcIC) at the start time `t`.
std::string describeInitFailure(const ModelEval &ev,
                                const Integrator &integrator,
                                const StepStatus &status, double t);

} // namespace ldae::runtime
