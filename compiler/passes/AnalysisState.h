// What the passes hand each other: the model, the structure after
// Pantelides (augmented equations and variable derivative chains), the
// chosen dummy derivatives and the system being built. Internal to
// compiler/passes; each pass reads what earlier passes left here.
#pragma once

#include "graph/BipartiteGraph.h"
#include "ir/DaeSystem.h"
#include "ir/Evaluate.h"
#include "passes/Pipeline.h"
#include "passes/SystemStructure.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace ldae::passes {

/// An eliminated alias: `var` equals `value` (over the kept variables).
struct Alias {
  ir::VarId var;
  ir::ExprRef value;
};

/// One row of the augmented system: an equation of the model or a time
/// derivative of one.
struct Row {
  ir::ExprRef residual = nullptr;
  int equation = 0; // index into AnalysisState::equations
  int times = 0;    // how often equations[equation] was differentiated
  int next = -1;    // the row of its derivative, or -1
};

/// A choice of dummy derivatives: for each unknown (index into
/// AnalysisState::unknowns), the lowest order that is a dummy derivative,
/// or highest[j] + 1 when none is.
using DummyChoice = std::vector<int>;

struct AnalysisState {
  AnalysisState(ir::Model &model, DiagnosticEngine &diags,
                const PipelineOptions &opts, AnalysisResult &result)
      : model(model), diags(diags), opts(opts), result(result) {}

  ir::Model &model;
  DiagnosticEngine &diags;
  const PipelineOptions &opts;
  AnalysisResult &result;

  // alias
  std::vector<Alias> aliases;
  std::vector<char> eliminated; // by VarId

  // matching: canonical orders (by name / equation key, never by source
  // position, so shuffling the model changes nothing).
  std::vector<ir::VarId> unknowns;       // continuous unknowns
  std::vector<int> unknownIndex;         // VarId -> index in unknowns or -1
  std::vector<int> equations;            // indices into model.equations
  std::vector<int> originalOrder;        // highest order of each unknown
  graph::BipartiteGraph merged;          // equations x unknowns (orders merged)
  graph::Matching mergedMatching;
  bool matchingCurrent = false; // merged/unknowns/equations match the model
  std::vector<int> nameRank;    // see nameRanks()

  // pantelides
  bool reduced = false;
  std::vector<Row> rows;                 // first the equations, then derivatives
  std::vector<int> highest;              // highest order of each unknown
  int maxTimes = 0;

  // dummy-derivatives: choices[0] is the initial one
  std::vector<DummyChoice> choices;
  /// Per choice: top-level pivot (rows of the ambiguous blocks, expressions
  /// over Variable nodes before layout substitution), square.
  std::vector<std::vector<ir::ExprRef>> pivots;
  std::vector<unsigned> pivotSizes;

  // system
  ir::DaeSystem system;
  bool haveSystem = false;
  /// Per state set: row of the residual matched to each unknown (BLT).
  std::vector<graph::Matching> systemMatchings;
  std::vector<graph::BipartiteGraph> systemGraphs;
  /// Per state set, the slots each residual reads (see SystemStructure.h).
  std::vector<SystemReads> systemReads;

  /// Rank of each variable's name (by VarId): equal names rank equal, and
  /// ranks order like the names. Sorting by rank instead of by name
  /// compares each pair of strings once, not once per sort.
  const std::vector<int> &nameRanks();

  /// "file:line" of a location, or "" when it has none.
  std::string where(SourceLoc loc) const;
  /// The user's text of model equation `e` (index into model.equations).
  std::string equationText(int e) const;
  /// Values of leaves at the start point: start values of variables,
  /// zero for derivatives, parameter values.
  ir::EvalEnv startEnv() const;
};

/// The passes, in pipeline order. Each returns false after reporting an
/// error that stops the pipeline.
bool runAliasElimination(AnalysisState &s);
bool runMatching(AnalysisState &s);
bool runDmDiagnosis(AnalysisState &s);
bool runPantelides(AnalysisState &s);
bool runDummyDerivatives(AnalysisState &s);
bool runBlt(AnalysisState &s);
bool runPrune(AnalysisState &s);
bool runInitialization(AnalysisState &s);

/// Builds the DaeSystem from the rows and dummy choices (used by
/// dummy-derivatives and, with no reduction, by `--method raw`).
bool buildSystem(AnalysisState &s);

/// How to name the rows and columns of a graph in a singularity message.
struct SingularityNames {
  std::function<SourceLoc(int)> rowLoc;
  std::function<std::string(int)> rowText;
  std::function<std::string(int)> colName;
  std::function<SourceLoc(int)> colLoc;
};

/// If `m` is not a complete matching of `g` (rows and allowed columns),
/// reports the Dulmage–Mendelsohn diagnosis of the `system` ("model" or
/// "initialization") and returns true; fills the result's
/// over/underDetermined lists when `record` is set.
bool diagnoseSingular(AnalysisState &s, const char *system,
                      const graph::BipartiteGraph &g, const graph::Matching &m,
                      const SingularityNames &names,
                      const std::vector<char> &colAllowed, bool record);

/// Lists `items` as `'a', 'b' and 'c'` (quoted).
std::string quotedList(const std::vector<std::string> &items);

} // namespace ldae::passes
