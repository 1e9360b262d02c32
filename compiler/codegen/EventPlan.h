// The events block of the C ABI (ldae_model, ABI 6; docs/events.md) as the
// code plan holds it: the tables, checked against the system, and the
// expressions of its three functions (event_update, time_events, asserts),
// which lowerToPlan turns into plan functions like any outputs.
#pragma once

#include "codegen/CodePlan.h"
#include "ir/DaeSystem.h"
#include "support/Expected.h"

#include <string>
#include <vector>

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

/// Fills the tables of `plan` from sys.events, sys.dummyOf and
/// sys.originalRow; fails naming the first table that does not fit the
/// system (a count, an index out of range, a missing expression).
/// `sources` resolves assert origins ("" without it).
Expected<bool> planEventTables(const ir::DaeSystem &sys, EventPlan &plan,
                               const SourceManager *sources);

/// The values of the three event functions, in their output order.
struct EventFunctionValues {
  std::vector<ir::ExprRef> update, timeEvents, asserts;
};
EventFunctionValues eventFunctionValues(const ir::EventSystem &events);

} // namespace ldae::codegen
