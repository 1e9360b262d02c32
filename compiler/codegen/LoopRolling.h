// Loop rolling (docs/codegen.md, "Loops"): repeated stores of one plan
// function moved into loops, long sums into reductions. A rewrite of the
// plan alone, so it sees plan types and never the IR or the lowering.
#pragma once

#include "codegen/CodePlan.h"

namespace ldae::codegen {

/// Functions with fewer stores stay straight-line code (small models gain
/// nothing from loops and read better unrolled).
constexpr unsigned kLoopMinStores = 64;
/// A shape becomes a loop when at least this many stores share it.
constexpr unsigned kLoopMinCount = 8;
/// Stores whose expression has more nodes than this stay straight-line
/// (a loop recomputes subexpressions shared between its instances).
constexpr unsigned kLoopMaxBody = 64;

/// A sum with at least this many terms (a ground node's current balance)
/// has its runs of terms of one shape folded by reduction loops.
constexpr unsigned kReductionMinTerms = 64;

/// Folds runs of at least kLoopMinCount same-shaped terms of long sums into
/// Reduce nodes, then moves the stores of `fn` that share an expression
/// shape with at least kLoopMinCount others into loops; the rest stays
/// straight-line, in the same order of operations. Runs before chunking;
/// leaves `fn` without dead nodes.
void rollLoops(PlanFunction &fn);

} // namespace ldae::codegen
