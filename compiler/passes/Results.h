// The typed results the passes hand each other, in pipeline order. Each
// pass's class says which it reads, updates and produces (TypedPass in
// Pass.h); the runner keeps them in one ResultStore. "build-system"
// produces the ir::DaeSystem itself. Internal to compiler/passes.
#pragma once

#include "graph/BipartiteGraph.h"
#include "ir/DaeSystem.h"
#include "passes/Pipeline.h"
#include "passes/SystemStructure.h"

#include <vector>

namespace ldae::passes {

/// An eliminated alias: `var` equals `value` (over the kept variables).
struct Alias {
  ir::VarId var;
  ir::ExprRef value;
};

/// "alias": the eliminated variables (the model is rewritten in place).
struct AliasResult {
  std::vector<Alias> aliases;   // sorted by name
  std::vector<char> eliminated; // by VarId, over the model's variables
};

/// "matching": unknowns and equations in canonical order (by name and
/// equation key, never by source position, so shuffling the model changes
/// nothing) and their matching with derivative orders merged.
struct MatchingResult {
  std::vector<ir::VarId> unknowns; // continuous unknowns
  std::vector<int> unknownIndex;   // VarId -> index in unknowns or -1
  std::vector<int> equations;      // indices into model.equations
  std::vector<int> originalOrder;  // highest order of each unknown
  graph::BipartiteGraph merged;    // equations x unknowns (orders merged)
  graph::Matching matching;
};

/// One row of the augmented system: an equation of the model or a time
/// derivative of one.
struct Row {
  ir::ExprRef residual = nullptr;
  int equation = 0; // index into MatchingResult::equations
  int times = 0;    // how often that equation was differentiated
  int next = -1;    // the row of its derivative, or -1
};

/// "pantelides": the augmented system, first the equations (in the
/// matching's order), then their derivatives.
struct IndexReduction {
  std::vector<Row> rows;
  std::vector<int> highest; // highest order of each unknown
  int maxTimes = 0;         // most differentiations of one equation
  /// The index of the rows handed on: 1 when reduced, the structural index
  /// of the model as written otherwise (`--method raw`).
  int handedIndex = 1;
};

/// A choice of dummy derivatives: for each unknown (index into
/// MatchingResult::unknowns), the lowest order that is a dummy derivative,
/// or highest[j] + 1 when none is.
using DummyChoice = std::vector<int>;

/// A block of the dummy-derivative selection whose choice is made at run
/// time (numeric/StatePivot.h): at its level, `rows` equations over the
/// `forced` columns (dummies chosen above) and the `candidates`, of which
/// rows - forced become dummies; the others are the states, through
/// s = A c with the selection matrix A (ir::DynamicStateSet).
struct DynamicBlock {
  int level = 0;
  unsigned rows = 0;
  std::vector<ir::VarKey> forced, candidates; // unknowns at the block's order
  /// rows x (forced + candidates), column-major, over Variable nodes before
  /// layout substitution.
  std::vector<ir::ExprRef> jacobian;
  /// Indices into candidates of the dummies at the start point.
  std::vector<int> startDummies;
};

/// "dummy-derivatives": the candidate state sets, choices[0] the initial
/// one.
struct DummyChoices {
  std::vector<DummyChoice> choices;
  /// Per choice: top-level pivot (rows of the ambiguous blocks, expressions
  /// over Variable nodes before layout substitution), square.
  std::vector<std::vector<ir::ExprRef>> pivots;
  std::vector<unsigned> pivotSizes;
  /// Blocks too large to enumerate, chosen at run time (the same in every
  /// choice): all their candidates' next derivatives are dummies in
  /// `choices`, and build-system adds the state set equations.
  std::vector<DynamicBlock> dynamic;
};

/// "blt" (and again "prune"): per state set of the DaeSystem, the slots
/// each residual reads, the solved-for incidence and its matching.
struct BltResult {
  std::vector<SystemReads> reads;
  std::vector<graph::BipartiteGraph> graphs;
  std::vector<graph::Matching> matchings; // residual -> what it solves for
};

/// "init": what the initialization system can honour. (Issue 12's
/// block-by-block initialization adds its blocks here.)
struct InitResult {
  InitReport report;
};

class PassContext;

/// The reported variables of a system: every user variable (aliases
/// included) and der(x) right after x where the model differentiates x,
/// in model order, or the requested outputs only, in the order requested
/// (a requested parameter is left to the runtime); with their kind, unit,
/// description and alias (ir::SystemOutput). `subst` maps model nodes to
/// the system's slots. False after reporting an unknown output name. (SystemBuilder.cpp; the
/// SGA's system reports the same outputs.)
bool buildOutputs(PassContext &pc, const AliasResult &alias,
                  const MatchingResult &mr, VarSubstitution &subst,
                  std::vector<ir::SystemOutput> &out);

} // namespace ldae::passes
