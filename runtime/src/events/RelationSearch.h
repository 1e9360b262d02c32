// The event iteration's way out of a cycle through relation values: the
// consistent combination of the relations coupled to the cycling ones,
// found by trying each (docs/events.md, "Relations that contradict their
// point").
#pragma once

#include "events/EventLoop.h"
#include "model/ModelEval.h"

#include <string>
#include <vector>

namespace ldae::runtime {

/// At an event iteration that comes back to relation values whose solved
/// point contradicted them (a Schmitt trigger at its switching instant:
/// the lower limit's point says `v < lower` is false, the linear branch's
/// point says it is true, and only the upper limit is consistent), tries,
/// as the mixed-system solvers of Dymola and OpenModelica do, every
/// combination of the `cycling` relations and the relations coupled to
/// them (those that change a residual row a cycling one changes), each
/// solved from (t, y, y') by `reinit` in state set `set`. The one
/// combination whose solved point gives back its own values is set in
/// ev's discrete values and its point in (y, y'), the integrator
/// restarted there. None, or several (ldaec does not choose between
/// consistent points), or more than kMaxCoupledRelations coupled: false,
/// with `failure` saying which.
bool chooseConsistentRelations(ModelEval &ev, int set, double t,
                               std::vector<double> &y, std::vector<double> &yp,
                               const std::vector<int> &cycling,
                               const Reinitialize &reinit,
                               std::string &failure);

/// The same search for a cycle that runs through discrete variables too,
/// at fixed pre() values: a friction element leaving w_rel = 0 (MSL's
/// PartialFriction) whose startForward, solved, gives a point that says
/// startBackward, and back, while only `locked` is consistent. Its unknowns
/// are the Booleans and relations the residual rows of the cycle read
/// (those of the cycling values, probed at the current values and at
/// `other`, the cycle's other state), as OpenModelica's mixed-system
/// search takes the Boolean unknowns of the system; a combination stands
/// when the update at its solved point gives all of them back.
bool chooseConsistentValues(ModelEval &ev, int set, double t,
                            std::vector<double> &y, std::vector<double> &yp,
                            const std::vector<int> &cycling,
                            const std::vector<double> &other,
                            const Reinitialize &reinit, std::string &failure);

/// Coupled relations beyond this many (2^n solves) are not searched.
inline constexpr size_t kMaxCoupledRelations = 10;

} // namespace ldae::runtime
