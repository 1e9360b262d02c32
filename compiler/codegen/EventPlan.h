// The events block of the C ABI (ldae_model, ABI 6; docs/events.md) as the
// code plan holds it: the tables, checked against the system, and the
// expressions of its three functions (event_update, time_events, asserts),
// which lowerToPlan turns into plan functions like any outputs.
#pragma once

#include "ir/DaeSystem.h"
#include "support/Expected.h"

#include <string>
#include <vector>

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

/// Every table empty and every function -1 for a model without events.
struct EventPlan {
  std::vector<std::string> discreteNames;
  std::vector<double> discreteStart;
  std::vector<int> discreteKind; // LDAE_DISCRETE_*
  std::vector<int> rootRelation; // per root; empty without discrete values
  std::vector<int> reinitTarget;
  std::vector<std::string> terminateMessage;
  /// out = [new discrete values | reinit values | reinit fired |
  /// terminate fired] (ldae_model::event_update).
  int update = -1;
  std::vector<int> thresholdRelation, sampleDiscrete;
  /// out = [thresholds | start, interval of each sample, in pairs].
  int timeEvents = -1;
  std::vector<std::string> assertMessage, assertOrigin;
  std::vector<int> assertLevel;
  int asserts = -1; // out = 1 (holds) or 0 per assert
  std::vector<int> modeDiscrete;
  std::vector<double> modeValues;
  /// Per state set, n entries each; empty: NULL in the ABI.
  std::vector<std::vector<int>> dummyOf, originalRow;

  unsigned numDiscrete() const { return discreteNames.size(); }
};

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
