// The runtime's public C++ API: integrate a compiled model (the C ABI
// struct ldae_model) with IDA or CVODE from a consistent initial point,
// switching state sets when their pivot matrix degrades, and collect the
// results. The driver (compiler/driver), the C entry point of emitted
// programs and the benchmarks call only this header, ResultWriter.h and
// Plot.h.
#pragma once

#include "ldae/model.h"
#include "support/Expected.h"

#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ldae::runtime {

/// Which SUNDIALS integrator runs the model. Auto: CVODE (BDF) when the
/// model is an explicit ODE (ldae_model::explicit_ode), IDA otherwise.
enum class IntegratorChoice { Auto, Ida, CvodeBdf, CvodeAdams };

/// The spellings of --integrator (ldaec and emitted programs alike).
struct IntegratorSpelling {
  const char *name;
  IntegratorChoice choice;
};
inline constexpr IntegratorSpelling kIntegratorSpellings[] = {
    {"auto", IntegratorChoice::Auto},
    {"ida", IntegratorChoice::Ida},
    {"cvode", IntegratorChoice::CvodeBdf},
    {"cvode-bdf", IntegratorChoice::CvodeBdf},
    {"cvode-adams", IntegratorChoice::CvodeAdams}};

/// The choice spelled `text`, or nothing.
inline std::optional<IntegratorChoice> parseIntegrator(std::string_view text) {
  for (const IntegratorSpelling &s : kIntegratorSpellings)
    if (text == s.name)
      return s.choice;
  return std::nullopt;
}

struct SimResult;

/// Takes a run's rows as they become final, in time order, so that a long
/// run holds none of them (the command line's result file: docs/results.md,
/// "Rows written as the run goes"). The event iteration may take back the
/// rows of the time it is at, so the rows of a time are handed on once a
/// later time is reached, and the last ones when the run ends.
class RowSink {
public:
  virtual ~RowSink() = default;
  /// Before the first row: the result's columns, their info and the run's
  /// parameters (its rows empty).
  virtual Expected<bool> begin(const SimResult &header) = 0;
  /// One row, time first. An Error ends the run (SimResult::writeFailure).
  virtual Expected<bool> row(const std::vector<double> &row) = 0;
};

/// What the user asked for; unset values fall back to the model's
/// experiment annotation, then to start 0, stop 1, rtol 1e-6,
/// atol = rtol, interval (stop - start) / 500.
struct SimOptions {
  std::optional<double> start, stop, rtol, atol, interval;
  /// Report every internal step instead of the `interval` grid.
  bool everyStep = false;
  /// Report at exactly these increasing times in (start, stop] instead of
  /// the `interval` grid (the start row is always reported). Without
  /// `stop`, the last of them is the stop time.
  std::vector<double> times;
  /// Reported columns by name (outputs, or unknowns when the model has no
  /// outputs); empty: all.
  std::vector<std::string> outputs;
  /// Progress bar on stderr when it is a terminal and the run is long.
  bool progress = true;
  /// Where initialization reports, state switches and warnings go
  /// (nullptr: nowhere).
  std::ostream *log = nullptr;
  IntegratorChoice integrator = IntegratorChoice::Auto;
  /// Whether IDA's local error test includes the algebraic unknowns
  /// (IDASetSuppressAlg). Unset: the default rule of docs/runtime.md.
  std::optional<bool> algebraicErrorTest;
  /// Parameter values overriding the model's defaults, by name. What reads
  /// them (bound parameters, start values) is evaluated again
  /// (ldae_model::bind); a structural parameter is an Error naming it
  /// (it needs a recompile).
  std::map<std::string, double> params;
  /// Start values overriding the model's, by unknown name (`x` for
  /// x.start). A name that is no unknown of the compiled model (solved
  /// out, an alias) is an Error saying so: its start needs a recompile.
  std::map<std::string, double> starts;
  /// Variable structure (ldae_model::n_mode > 0): the model of the mode
  /// whose mode values (ldae_model::mode_discrete order) are `values`,
  /// built on first use and kept alive by the provider. An Error says why
  /// it cannot be built. Unset: a change of mode ends the run (status 3)
  /// naming the condition.
  std::function<Expected<const ldae_model *>(const std::vector<double> &values)>
      modeProvider;
  /// Polled after every integrator step: true ends the run there, its rows
  /// kept (SimResult::interrupted; a signal, Python's Ctrl-C). Unset: never.
  std::function<bool()> interrupted;
  /// Set: the rows go to it as the run produces them and SimResult::rows
  /// stays empty. Unset: the rows are kept in SimResult::rows.
  RowSink *rowSink = nullptr;
};

/// Counters of one run (summed over all IDA re-initializations).
struct SimStats {
  long steps = 0;
  long residualEvals = 0; ///< including those for difference quotients
  long jacobianEvals = 0;
  long errorTestFailures = 0;
  long convergenceFailures = 0; ///< nonlinear solver failures
  long stateSwitches = 0;
  long rootsFound = 0;
  long events = 0;       ///< state and time events handled (initial excluded)
  long timeEvents = 0;   ///< of which time events (sample, time relations)
  long modeSwitches = 0; ///< changes of structure (variable-structure models)
  long jumps = 0;        ///< events after which continuous unknowns jumped
  double maxDrift = 0; ///< largest |model.drift| seen at output points
  /// Projections onto the constraints (`--method sga|ode`: the start,
  /// every step, output rows).
  long projections = 0;
  double wallTime = 0; ///< seconds, initialization included
  double initTime = 0; ///< seconds spent finding the initial point
  bool sparse = false; ///< KLU (true) or dense LU (false)
  std::string integrator; ///< "IDA", "CVODE (BDF)", "CVODE (Adams)"
  int n = 0;           ///< unknowns
};

/// What a column of the result is (result files, plots).
enum class ColumnKind { Time, Continuous, Derivative, Discrete, Parameter };

/// What a result file and a plot say of one column.
struct ColumnInfo {
  ColumnKind kind = ColumnKind::Continuous;
  std::string unit;        ///< "" when the model gives none
  std::string description; ///< "" when the model gives none
  /// 0: a value of its own; +(j + 1): equals column j; -(j + 1): equals
  /// minus column j (ldae_model::output_alias, mapped to result columns).
  int alias = 0;
};

/// A parameter as the run used it (result files carry every one).
struct ParamValue {
  std::string name;
  double value = 0;
  std::string unit, description;
};

/// The run's table and outcome.
struct SimResult {
  int status = 0;      ///< 0 ok, 3 numerical failure (rows kept up to it)
  std::string failure; ///< the message when status != 0
  /// SimOptions::interrupted ended the run (status 3, the rows so far
  /// kept, `failure` says where).
  bool interrupted = false;
  std::string model;   ///< the model's name (plot titles, .mat description)
  std::vector<std::string> columns; ///< "time", then the reported names
  std::vector<ColumnInfo> info;     ///< one per column
  std::vector<std::vector<double>> rows;
  /// The rows the run produced (in `rows`, or handed to
  /// SimOptions::rowSink), and the time of the last.
  size_t rowCount = 0;
  double lastTime = 0;
  /// The RowSink's Error that ended the run ("" when it took every row).
  std::string writeFailure;
  /// Every parameter of the model with the value of this run.
  std::vector<ParamValue> params;
  SimStats stats;
};

/// The most rows the interval grid may have (start row included): 10^8
/// rows of one column are already 1.6 GB of CSV text.
inline constexpr double kMaxOutputRows = 1e8;

/// Rows of the interval grid from `start` to `stop` (> start), the start
/// row included.
double outputRows(double start, double stop, double interval);

/// The error for a grid of more than kMaxOutputRows rows.
std::string tooManyRowsMessage(double start, double stop, double interval);

/// Integrates `model`. Returns an Error only for bad options (an unknown
/// output or parameter name, stop before start, a non-positive tolerance);
/// numerical failures come back as status 3 with the message in `failure`.
Expected<SimResult> simulate(const ldae_model &model, const SimOptions &opts);

/// Prints the counters, one per line.
void printStats(const SimStats &stats, std::ostream &out);

} // namespace ldae::runtime
