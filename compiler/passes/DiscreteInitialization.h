// The discrete part of the initialization (MLS 8.6): the pre() values of
// discrete variables are unknowns of the initialization, which initial
// equations of discrete values determine through the discrete equations.
// StateGraph's steps write `pre(newActive) = pre(localActive)` with
// `localActive = pre(newActive)` and `active = localActive` given by
// `initial equation active = true`; OpenModelica's pre3 writes
// `initial equation xd = 2` for `when initial() then xd = pre(xd) + 4*pre(x)`,
// which gives pre(xd) = 2 - 4x.
//
// Each such initial equation is read with every discrete variable replaced
// by the value the first round of the initial event gives it (its update
// with initial() rising), so it becomes an equation over pre() values,
// continuous unknowns, time and parameters. The equations are matched to
// the pre() values they are linear in and solved in dependency order; a
// pre() value no equation determines keeps its start value (the value the
// first round reads today), one with `fixed = true` is its start.
#pragma once

#include "ir/DaeSystem.h"

#include <span>
#include <vector>

namespace ldae::passes {

class PassContext;
struct EventResult;

/// What the solve needs of a slot of the discrete state.
struct DiscreteInitSlot {
  ir::DiscreteKind kind = ir::DiscreteKind::Variable;
  ir::VarId var = 0;  // Variable slots
  bool fixed = false; // pre(v) = v.start is an equation of the initialization
};

/// Solves `equations` (initial equations of discrete values, as written:
/// Variable and Pre nodes of discrete variables) for pre() values. On
/// success, preValue[k] is the value of slot k's pre() during the
/// initialization, over the model's continuous Variable nodes, time and
/// user parameters, or null where no equation determines it. Reports a
/// located error for an equation that determines no pre() value (none it
/// reads is free, or it is not linear in one) or a cycle, and returns
/// false.
bool solveDiscreteInitialization(PassContext &pc, const EventResult &ev,
                                 std::span<const DiscreteInitSlot> slots,
                                 std::span<const ir::Equation> equations,
                                 std::vector<ir::ExprRef> &preValue);

} // namespace ldae::passes
