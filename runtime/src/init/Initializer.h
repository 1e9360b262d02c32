// The one initializer of a run: from the start values (or a point carried
// over) to a consistent initial point, choosing among the paths of init/
// (the integrator's own index-1 solve, the sparse index-1 and general
// Newton iterations, the dense one along the jump space) and, for a model
// with homotopy(), the continuation from its simplified model first.
//
// The integrator sits above init/ (docs/architecture.md, "The runtime's
// rooms"): the initializer reaches it only through InitTarget, which the
// run loop implements with the integrator.
#pragma once

#include "init/InitOutcome.h"
#include "model/ModelEval.h"

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace ldae::runtime {

/// Where the initializer's points go and what it asks of the integrator:
/// restarts at a point, the integrator's own start completion (IDACalcIC)
/// and the point it holds. Also the messages of the failures above init/
/// (the run's failure report), so that they read as during the run.
class InitTarget {
public:
  virtual ~InitTarget() = default;
  /// Restarts at (t, y, y') with state set `set`; the user's message when
  /// that fails.
  virtual std::optional<std::string> restart(int set, double t, const double *y,
                                             const double *yp) = 0;
  /// Completes the start by the integrator's own index-1 solve towards the
  /// first output time `tNext`; false when it fails.
  virtual bool completeStart(double tNext) = 0;
  /// The point held (after restart or completeStart).
  virtual const double *y() const = 0;
  virtual const double *yp() const = 0;
  /// The message of a domain error in residual row `row` of `set` at the
  /// unknowns `y`, met initializing at `t`.
  virtual std::string describeDomainError(int set, int row, const double *y,
                                          double t) const = 0;
};

/// Whether the start is approached by the continuation of homotopy().
enum class ContinuationKind {
  IfModelHasHomotopy, ///< the run's start
  None,               ///< from the start values again (a mode's restart)
};

/// Finds a consistent initial point at `t0` from the start vector (y, y')
/// the target holds (the model's start values) and leaves the target
/// restarted there. A model with homotopy() is initialized by the
/// continuation from its simplified model first (with `continuation`), as
/// OpenModelica does by default: the simplified model is how the library's
/// author picks the solution meant among several (the operating point of a
/// Schmitt trigger, the branch of a diode), and a direct solve from the
/// start values may land on another one with no sign of it. Where the
/// continuation fails, the actual model is solved from the start values.
/// `tNext` is the first output time (IDACalcIC's direction). The outcome's
/// `failure` is the user's message when !ok; y and y' are the point.
InitOutcome initialize(ModelEval &ev, InitTarget &target, int set, double t0,
                       double tNext, ContinuationKind continuation,
                       std::ostream *log);

} // namespace ldae::runtime
