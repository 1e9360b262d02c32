// What every pass gets besides the typed results it reads (Results.h): the
// model (which alias elimination and build-system rewrite in place), the
// diagnostics, the options and the `--analyze` report each pass adds to.
// Also the helpers several passes share for their messages. Internal to
// compiler/passes.
#pragma once

#include "graph/BipartiteGraph.h"
#include "ir/Evaluate.h"
#include "ir/Model.h"
#include "passes/Pipeline.h"

#include <functional>
#include <string>
#include <vector>

namespace ldae::passes {

struct EventResult;

class PassContext {
public:
  PassContext(ir::Model &model, DiagnosticEngine &diags,
              const PipelineOptions &opts, AnalysisResult &report)
      : model(model), diags(diags), opts(opts), report(report) {}

  ir::Model &model;
  DiagnosticEngine &diags;
  const PipelineOptions &opts;
  AnalysisResult &report;
  /// The "events" pass's result (it runs first), for the passes that
  /// build a system by a route other than a typed pass (sga-system).
  const EventResult *events = nullptr;
  /// Set by a pass that has produced the final system by another route
  /// (sga-check): the passes after it do not run.
  bool finished = false;
  /// The start or a change of mode may make states jump along T(E, F) of
  /// the model as written (a mode reached during a run; differentiated
  /// aliases kept because their start values differ): the system keeps
  /// its rows as written, with no causal form and no pruning, so that the
  /// runtime has that pencil (ldae_model::dummy_of, original_row).
  bool jumpsMatter = false;

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
  /// startEnv with the discrete variables primed as the run primes them
  /// before it initializes (runtime EventLoop::prime): the update's value
  /// at the start point with initial() true, pre() values at their start.
  /// For the initialization's analysis only: what other passes decide
  /// from start values must not read values of the first event.
  ir::EvalEnv initializationEnv() const;

private:
  std::vector<int> nameRank_; // a cache: variables are only appended
  /// The primed current values (initializationEnv), computed once.
  mutable std::vector<std::pair<ir::ParamId, double>> primed_;
  mutable bool primedDone_ = false;
};

/// How to name the rows and columns of a graph in a singularity message.
struct SingularityNames {
  std::function<SourceLoc(int)> rowLoc;
  std::function<std::string(int)> rowText;
  std::function<std::string(int)> colName;
  std::function<SourceLoc(int)> colLoc;
};

/// If `m` is not a complete matching of `g` (rows and allowed columns),
/// reports the Dulmage–Mendelsohn diagnosis of the `system` ("model" or
/// "initialization") and returns true; fills the report's
/// over/underDetermined lists when `record` is set. (DmDiagnosis.cpp; the
/// "blt" and "init" passes diagnose their systems with it too.)
bool diagnoseSingular(PassContext &ctx, const char *system,
                      const graph::BipartiteGraph &g, const graph::Matching &m,
                      const SingularityNames &names,
                      const std::vector<char> &colAllowed, bool record);

/// The name of an external function an equation of `m` calls with
/// arguments that read the unknowns or time, "" if none: the passes that
/// judge a model at points a run does not reach (random points, the SGA's
/// sampling) do not call C code there (it may not survive them).
std::string externalOfUnknowns(const ir::Model &m);

/// Lists `items` as `'a', 'b' and 'c'` (quoted).
std::string quotedList(const std::vector<std::string> &items);
/// The first of `items` quoted (at most 8), then "(and N more)" of
/// `total` (items.size() when 0): a singular model of thousands of
/// unknowns names a few, not every one, in its message.
std::string quotedFew(const std::vector<std::string> &items, size_t total = 0);

} // namespace ldae::passes
