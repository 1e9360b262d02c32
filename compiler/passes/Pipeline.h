// The public face of the analysis stage: runs the pipeline of the chosen
// method (the passes of Passes.def: alias elimination, matching,
// Dulmage–Mendelsohn diagnosis, Pantelides, dummy derivatives, building the
// system, BLT, output pruning, initialization) on a flat Model and returns
// the index-1 DaeSystem plus a report for `--analyze`.
#pragma once

#include "ir/DaeSystem.h"
#include "passes/Causalize.h"
#include "ir/Model.h"
#include "passes/Method.h"
#include "support/Diagnostics.h"

#include <nlohmann/json_fwd.hpp>

#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ldae::passes {

struct PipelineOptions {
  /// Which pipeline runs (pipelineFor): dummy derivatives (index 1), or
  /// raw (no index reduction: the model as written, made first order).
  /// sga and ode run the dd pipeline until their passes arrive (issue 14).
  Method method = Method::DummyDerivatives;
  /// Requested outputs (flat names, `der(x)` allowed); empty: everything.
  std::vector<std::string> outputs;
  /// Causalize and tear the index-1 system (`--causalize on|off`).
  bool causalize = true;
  bool timePasses = false;
  /// Only a report is asked for (`--analyze`, or no action): a model that
  /// is not well-posed gets warnings where a run would get errors.
  bool reportOnly = false;
  /// Variable structure: the values of the discrete values that choose the
  /// branches of structure-changing if-equations (EventSystem::modeDiscrete
  /// order) to build the system for; empty: their start values.
  std::vector<double> modeValues;
  /// Keep every alias between two differentiated variables as an equation
  /// (a mode reached during a run: the values carried over may differ, and
  /// the jump rule must see both). Otherwise kept only where their start
  /// values differ.
  bool keepStateAliases = false;
  /// Pass names after which the current state is printed to `log`.
  std::vector<std::string> printAfter;
  std::ostream *log = nullptr;
};

/// An equation index reduction differentiated.
struct DifferentiatedEquation {
  std::string equation; // as the user wrote it
  std::string location; // file:line
  int times = 0;
};

/// One candidate choice of states (dynamic state selection).
struct StateSetReport {
  std::vector<std::string> states;
  std::vector<std::string> dummies;
  /// The pivot matrix of the set printed as lsd expressions (row-major).
  std::vector<std::string> pivot;
  unsigned pivotSize = 0;
};

/// The initialization system and what it can honour.
struct InitReport {
  bool analyzed = false;
  int unknowns = 0;  // y and y' of the differential unknowns
  int equations = 0; // residuals + fixed start values + initial equations
  int dof = 0;       // unknowns - equations (negative: over-specified)
  std::vector<std::string> fixed;      // names with fixed = true
  std::vector<std::string> honoured;   // fixed values the model can take
  std::vector<std::string> conflicting;// over-determining fixed values
  std::vector<std::string> toFree;     // which of them to free
  std::vector<std::string> guesses;    // start values used only as guesses
  int initialEquations = 0;
  bool consistent = true;
};

/// One constraint the SGA found: the expression (lsd text, over the
/// unknowns and time) and the model equations it was derived from.
struct SgaConstraint {
  std::string expr;
  std::vector<std::string> from; // equation texts as the user wrote them
};

/// The geometric algorithm's verdict (seed 000 §3, seed 001 §3-4).
struct SgaReport {
  enum class Outcome { Unique, NotUnique, NoSolution };
  Outcome outcome = Outcome::Unique;
  /// dim P_f: unknowns (first-order form) minus independent constraints.
  int dof = 0;
  /// Derivatives the tangency conditions leave free (gauge freedom).
  int freeFunctions = 0;
  /// Constraint generations: [0] primary, [1] secondary, ...
  std::vector<std::vector<SgaConstraint>> generations;
  /// Variables whose evolution the model leaves free (gauge freedom).
  std::vector<std::string> undetermined;
  /// Equations implied by the others on P_f (over-determined, consistent).
  std::vector<std::string> redundant;
  /// For no_solution: the constraint that cannot hold, and its sources.
  std::optional<SgaConstraint> conflict;
  /// Steps of the algorithm until no new constraint appeared.
  int steps = 0;
  /// The point of a zero-dimensional P_f (name = value), when dof == 0.
  std::vector<std::pair<std::string, double>> point;
};

/// The Wong-sequence analysis of a linear model E x' = F x + f(t)
/// (seed 002), when the model (or its linear part) is linear with
/// constant coefficients.
struct LinearReport {
  bool regular = false;
  int index = 0;
  int dimV = 0;
  int dimW = 0;
  /// Not well-posed: the free directions (combinations of variables) of a
  /// singular pencil, as text: the first kMaxDirectionTexts of freeCount.
  std::vector<std::string> freeDirections;
  size_t freeCount = 0;
  /// Inconsistent inputs: why.
  std::string conflict;
};

struct PassTiming {
  std::string name;
  double seconds = 0;
};

/// The "events" pass: the discrete state (docs/events.md).
struct EventsReport {
  /// Each discrete value as `name (kind)`: `heat (variable)`,
  /// `h <= 0 (relation)`.
  std::vector<std::string> discrete;
  std::vector<std::string> roots;          // lsd, over the model
  std::vector<std::string> timeThresholds; // lsd
  int samples = 0;
  int reinits = 0;
  int asserts = 0;
  /// The discrete values choosing the structure (variable structure).
  std::vector<std::string> mode;
};

struct AnalysisResult {
  std::string model;
  /// The user's parameters (not constants), and those among them whose
  /// value fixed the structure (a new value needs a recompile; the others
  /// change at run time without one).
  std::vector<std::string> parameters;
  std::vector<std::string> structuralParameters;
  int variables = 0; // continuous unknowns of the flat model
  int equations = 0; // equations of the flat model
  int aliasesRemoved = 0;
  std::vector<std::string> aliases; // "a = b", "c = -d", "e = 0"
  bool singular = false;            // structurally singular model
  std::vector<std::string> overDetermined;  // equation texts
  std::vector<std::string> underDetermined; // variable names
  std::optional<int> structuralIndex; // of the system after alias elimination
  /// Pryce's structural index of the model as written (--analyze).
  std::optional<int> structuralIndexAsWritten;
  /// Equals the structural index: ldaec does not compute more yet (the SGA
  /// stage may refine it where structure is fooled by cancellation).
  std::optional<int> differentiationIndex;
  int dof = 0; // number of states of the index-1 system (the SGA's dim P_f
               // where the two disagree)
  /// The structural count where the SGA found another (structure fooled).
  std::optional<int> structuralDof;
  std::vector<std::string> states;
  std::vector<std::string> dummies;
  std::vector<DifferentiatedEquation> differentiated;
  std::vector<int> bltBlocks; // sizes, in solve order
  int systemUnknowns = 0;     // size of the DaeSystem
  int prunedUnknowns = 0;     // removed by output-driven pruning
  std::vector<StateSetReport> stateSets;
  CausalResult causal;
  InitReport init;
  /// The SGA's verdict (the "sga" pass), when it ran.
  std::optional<SgaReport> sga;
  /// Why sga is empty when the pass did not run it ("" when it ran).
  std::string sgaNote;
  /// Wong sequences of the linear model, when it is linear.
  std::optional<LinearReport> linear;
  /// Le Vey's formal index of the system as written (seed 004).
  std::optional<int> formalIndex;
  /// Why formalIndex is empty (docs/indices.md), "" when it is set.
  std::string formalIndexNote;
  /// dim R_q^(s) (fibre dimension) for s = 0, 1, ...: the last two equal.
  std::vector<int> formalDimensions;
  /// The discrete state, when the model has one (the "events" pass).
  std::optional<EventsReport> events;
  std::vector<PassTiming> timings;
  std::optional<ir::DaeSystem> system;
};

/// Runs the pass list on `model` (modified in place); false after
/// reporting errors.
bool runPipeline(ir::Model &model, const PipelineOptions &opts,
                 DiagnosticEngine &diags, AnalysisResult &result);
/// The `--analyze` text report.
void printAnalysis(const AnalysisResult &result, std::ostream &out);
/// The `--analyze --json` report (schema: docs/analysis-json.md).
nlohmann::json analysisToJson(const AnalysisResult &result);
/// The index-1 system as a valid lsd model (`--emit reduced`).
std::string printReduced(const ir::DaeSystem &system);

/// Name and one-line summary of each pass, in pipeline order.
struct PassInfo {
  const char *name;
  const char *summary;
};
/// Every pass of Passes.def, in its order.
const std::vector<PassInfo> &passList();
/// Their names as "alias, matching, ..." (for messages and --help).
std::string passNames();

} // namespace ldae::passes
