// Pass "events" (docs/events.md, issue 15): the discrete part of a model
// leaves the continuous system. Runs first in every pipeline.
//
// Each discrete value gets a slot k of the discrete state; the pass appends
// two Parameters per slot after the user's parameters (flagged
// ir::Parameter::discrete): its current value at ParamId base + k and its
// pre() value at base + K + k. Continuous equations read those instead of
// discrete variables, relations (frozen between events) and pre(). What
// happens at an event (update, reinit, terminate, roots, time events,
// asserts) is kept here as expressions over the model's own Variable nodes;
// build-system and sga-system carry them over the layout rule
// (fillEvents) into DaeSystem::events.
#pragma once

#include "ir/DaeSystem.h"

#include <functional>
#include <span>
#include <vector>

namespace ldae::passes {

class PassContext;

/// The event part of a model, over the model's Variable nodes (before alias
/// elimination and the layout rule). Empty for a continuous model.
struct EventResult {
  ir::ParamId base = 0; // ParamId of slot 0's current value
  std::vector<ir::DiscreteValue> discrete;
  std::vector<ir::ExprRef> update; // per slot
  std::vector<ir::ExprRef> roots;  // lhs - rhs of each root relation
  std::vector<uint32_t> rootRelation;
  struct Reinit {
    ir::VarId var = 0;
    ir::ExprRef value = nullptr, fired = nullptr;
    SourceLoc loc;
  };
  std::vector<Reinit> reinits;
  std::vector<ir::TerminateUpdate> terminates;
  std::vector<ir::ExprRef> timeThresholds;
  std::vector<uint32_t> thresholdRelation;
  std::vector<std::pair<ir::ExprRef, ir::ExprRef>> samples;
  std::vector<uint32_t> sampleDiscrete;
  std::vector<ir::DelayInput> delays;
  std::vector<ir::AssertCheck> asserts;
  std::vector<uint32_t> modeDiscrete;
  std::vector<double> modeValues;

  bool empty() const { return discrete.empty() && asserts.empty(); }
  /// The Parameter node of slot k's current value, and of its pre().
  ir::ParamId current(size_t k) const {
    return base + static_cast<ir::ParamId>(k);
  }
  ir::ParamId pre(size_t k) const {
    return base + static_cast<ir::ParamId>(discrete.size() + k);
  }
};

/// After unknowns solved from their equations were substituted into
/// sys.events.update (`before`: the update before that): a solved unknown
/// reads discrete values too (MSL's table output reads its next event
/// time), and there the update now reads the values it gives them, where
/// that makes no cycle, as the sorted discrete equations do (MLS 8.6).
/// Read with the values of the round before, IntegerTable's getValue ran
/// before its first getNextTimeEvent at the initial event and indexed the
/// interval table that call builds (a crash in MSL's Interaction1).
void readUpdatedThroughSolved(ir::DaeSystem &sys,
                              const std::vector<ir::ExprRef> &before);

/// Moves `ev` into `sys` (events, roots; parameterValues/Names keep only
/// the user's parameters) through `apply`, which maps an expression over
/// the model's variables to the system's layout (alias values, then the
/// slots). A reinit of an alias goes to its representative's slot in its
/// sign; a reinit of a variable that is no state of `sys` is an error
/// naming it (false).
bool fillEvents(PassContext &pc, const EventResult &ev,
                const std::function<ir::ExprRef(ir::ExprRef)> &apply,
                ir::DaeSystem &sys);

/// Variable structure: `m` (as the events pass left it, before a mode was
/// chosen: pass no modeValues) with the constants `values` for the
/// discrete values ev.modeDiscrete, so an if-equation that switches
/// structure keeps one branch. The pass does this itself with
/// PipelineOptions::modeValues (or the start values).
void applyMode(ir::Model &m, const EventResult &ev,
               std::span<const double> values);

} // namespace ldae::passes
