// The extension module _ldaec: the driver's stages (Compilation.h) for
// Python. One Model is one compiled model; simulate() runs it with the GIL
// released, so several threads (a sweep's, or a GUI's) can run at once.
// Diagnostics are the command's own text: every stage writes into a
// string stream, and a failure becomes one of the exceptions of
// ldaec/errors.py carrying that text. The package ldaec (ldaec/*.py)
// wraps this module; users import that, not this (docs/python.md).
#include "Compilation.h"
#include "RowTable.h"
#include "ErrorKind.h"
#include "OutputSelection.h"
#include "RunRequest.h"

#include "ldae/ResultWriter.h"
#include "ldae/Simulation.h"
#include "passes/Method.h"
#include "passes/Pipeline.h"

#include <nlohmann/json.hpp>
#include <chrono>
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cassert>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace ldae;

namespace {

/// A failure of its kind and the text the command would print; translated
/// to the exception of ldaec.errors for the kind's exit code (ModelError,
/// UsageError or SimulationError) carrying the kind as `kind`.
struct StageError {
  driver::ErrorKind kind;
  std::string text;
};

/// The compile options of ldaec.compile().
struct CompileArgs {
  std::string path, model, method = "dd", jit = "auto", cacheDir;
  std::vector<std::string> outputs, overrides;
};

/// `value`, or a UsageError with the message of `parsed`'s Error.
template <typename T> T usable(Expected<T> parsed) {
  if (!parsed)
    throw StageError{driver::ErrorKind::BadOption, "error: " + parsed.error() + "\n"};
  return std::move(*parsed);
}

driver::CompileRequest compileRequest(const CompileArgs &a, bool reportOnly) {
  // As open() does: a NUL would cut the path short (compile('osc.lsd\0junk')
  // compiled osc.lsd).
  if (a.path.find('\0') != std::string::npos)
    throw StageError{driver::ErrorKind::BadOption, "error: the path contains a NUL character\n"};
  driver::CompileRequest req;
  req.path = a.path;
  req.modelName = a.model;
  req.overrides = a.overrides;
  req.outputs = a.outputs;
  driver::CompileChoices choices;
  choices.method = usable(driver::parseMethodOption(a.method));
  choices.jit = usable(driver::parseJitOption(a.jit));
  choices.cacheDir = a.cacheDir;
  driver::applyCompileChoices(choices, req);
  req.passes.reportOnly = reportOnly;
  return req;
}

/// The text a diagnostic of `id` with `message` draws (what the command
/// prints for a failed run or bad run options).
std::string diagnosticText(driver::Compilation &c, DiagId id,
                           const std::string &message) {
  std::ostringstream out;
  c.diagnostics().report(id, SourceLoc{}, {message});
  c.diagnostics().flush(out);
  return out.str();
}

/// One run's outcome: the runtime's result without its rows, which are in
/// `table` (handed to numpy as a view, to the writers as rows).
class Result {
public:
  Result(runtime::SimResult r, std::unique_ptr<python::RowTable> table,
         std::string log, std::string diagnostics)
      : r_(std::move(r)), table_(std::move(table)), log_(std::move(log)),
        diagnostics_(std::move(diagnostics)) {}

  /// The (rows x columns) values, a view of the table's block that keeps
  /// it alive.
  py::array_t<double> data() const {
    py::ssize_t rows = static_cast<py::ssize_t>(table_->rows());
    py::ssize_t cols = static_cast<py::ssize_t>(r_.columns.size());
    if (rows == 0)
      return py::array_t<double>(std::vector<py::ssize_t>{0, cols});
    // The sink's header is the result's (RowSink::begin).
    assert(table_->columns() == r_.columns.size());
    auto *owner = new std::shared_ptr<std::vector<double>>(table_->values());
    py::capsule keep(owner, [](void *p) {
      delete static_cast<std::shared_ptr<std::vector<double>> *>(p);
    });
    return py::array_t<double>(std::vector<py::ssize_t>{rows, cols},
                               (*owner)->data(), keep);
  }

  py::dict stats() const {
    const runtime::SimStats &s = r_.stats;
    py::dict d;
    d["steps"] = s.steps;
    d["residual_evals"] = s.residualEvals;
    d["jacobian_evals"] = s.jacobianEvals;
    d["error_test_failures"] = s.errorTestFailures;
    d["convergence_failures"] = s.convergenceFailures;
    d["state_switches"] = s.stateSwitches;
    d["roots_found"] = s.rootsFound;
    d["events"] = s.events;
    d["time_events"] = s.timeEvents;
    d["mode_switches"] = s.modeSwitches;
    d["jumps"] = s.jumps;
    d["max_drift"] = s.maxDrift;
    d["projections"] = s.projections;
    d["wall_time"] = s.wallTime;
    d["init_time"] = s.initTime;
    d["sparse"] = s.sparse;
    d["integrator"] = s.integrator;
    d["n"] = s.n;
    return d;
  }

  /// (name, kind, unit, description, alias) per column.
  py::list columns() const {
    static const char *kinds[] = {"time", "continuous", "derivative",
                                  "discrete", "parameter"};
    py::list out;
    for (size_t j = 0; j < r_.columns.size(); ++j) {
      runtime::ColumnInfo info;
      if (j < r_.info.size())
        info = r_.info[j];
      out.append(py::make_tuple(r_.columns[j],
                                kinds[static_cast<int>(info.kind)], info.unit,
                                info.description, info.alias));
    }
    return out;
  }

  /// (name, value, unit, description) per parameter.
  py::list params() const {
    py::list out;
    for (const runtime::ParamValue &p : r_.params)
      out.append(py::make_tuple(p.name, p.value, p.unit, p.description));
    return out;
  }

  void write(const std::string &path, const std::string &format) const {
    Expected<runtime::ResultFormat> f = runtime::resultFormat(path, format);
    if (!f)
      throw StageError{driver::ErrorKind::BadOption, "error: " + f.error() + "\n"};
    runtime::SimResult whole = r_;
    whole.rows = table_->rowVectors();
    Expected<bool> ok = runtime::writeResult(whole, path, *f);
    if (!ok)
      throw StageError{driver::ErrorKind::ModelError, "error: " + ok.error() + "\n"};
  }

  const runtime::SimResult &raw() const { return r_; }
  const std::string &log() const { return log_; }
  const std::string &diagnostics() const { return diagnostics_; }

private:
  runtime::SimResult r_;
  std::unique_ptr<python::RowTable> table_;
  std::string log_;         // initialization reports, warnings
  std::string diagnostics_; // what the command prints for a failure
};

/// A model parsed, analyzed and compiled once, run many times.
class Model {
public:
  explicit Model(const CompileArgs &args)
      : c_(std::make_unique<driver::Compilation>(compileRequest(args, false),
                                                 out_)) {
    // Compiling takes seconds for large models: other threads run.
    bool ok;
    {
      py::gil_scoped_release release;
      ok = c_->parse() && c_->analyze() && c_->compile();
    }
    if (!ok)
      throw StageError{driver::errorKindOfExitCode(c_->exitCode()), out_.str()};
    warnings_ = out_.str();
    out_.str("");
  }

  Result simulate(const driver::RunRequest &run) {
    usable(driver::checkFinite(run));
    runtime::SimOptions o = driver::runOptions(run, c_->request());
    std::ostringstream log;
    o.log = &log;
    auto table = std::make_unique<python::RowTable>();
    o.rowSink = table.get();
    // Ctrl-C: Python's handler only sets a flag, which the run polls (in
    // the main thread, every 50 ms of the run, taking the GIL for it): the
    // run stops within a step and KeyboardInterrupt is raised; the result
    // is dropped, as an exception drops a return value.
    bool signalled = false;
    auto lastCheck = std::chrono::steady_clock::now();
    o.interrupted = [&signalled, &lastCheck] {
      auto now = std::chrono::steady_clock::now();
      if (signalled || now - lastCheck < std::chrono::milliseconds(50))
        return signalled;
      lastCheck = now;
      py::gil_scoped_acquire acquire;
      signalled = PyErr_CheckSignals() != 0;
      return signalled;
    };
    std::optional<Expected<runtime::SimResult>> r;
    {
      py::gil_scoped_release release;
      r.emplace(c_->simulate(std::move(o)));
    }
    if (signalled)
      throw py::error_already_set(); // the KeyboardInterrupt Python set
    if (!*r)
      throw StageError{driver::needsRecompile(abi(), run)
                           ? driver::ErrorKind::NeedsRecompile
                           : driver::ErrorKind::BadOption,
                       diagnosticText(*c_, DiagId::ErrSimulationOptions,
                                      r->error())};
    std::string failure =
        (*r)->status != 0
            ? diagnosticText(*c_, DiagId::ErrSimulationFailed, (*r)->failure)
            : std::string();
    return Result(std::move(**r), std::move(table), log.str(), failure);
  }

  const ldae_model &abi() const { return c_->compiled().model(); }

  /// name -> default value, in the model's parameter order.
  py::dict parameters() const {
    py::dict d;
    const ldae_model &m = abi();
    for (int k = 0; k < m.n_params; ++k)
      d[py::str(m.param_names[k])] = m.param_values[k];
    return d;
  }

  std::vector<std::string> structural() const {
    std::vector<std::string> names;
    const ldae_model &m = abi();
    for (int k = 0; k < m.n_params; ++k)
      if (m.param_structural && m.param_structural[k])
        names.push_back(m.param_names[k]);
    return names;
  }

  static std::vector<std::string> names(const char *const *list, int n) {
    return std::vector<std::string>(list, list + n);
  }
  std::vector<std::string> unknowns() const {
    return names(abi().var_names, abi().n);
  }
  std::vector<std::string> outputNames() const {
    return names(abi().output_names, abi().n_outputs);
  }
  /// The names `patterns` select among outputNames(), for one run.
  std::vector<std::string>
  expandOutputs(const std::vector<std::string> &patterns) const {
    return usable(driver::expandOutputPatterns(patterns, outputNames()));
  }
  /// {name: start} of the compiled unknowns.
  py::dict starts() const {
    py::dict d;
    const ldae_model &m = abi();
    for (int i = 0; i < m.n; ++i)
      d[py::str(m.var_names[i])] = m.start_y[i];
    return d;
  }

  std::string name() const { return abi().name ? abi().name : ""; }
  double compileSeconds() const { return c_->compileSeconds(); }
  std::string backend() const {
    return codegen::describeBackend(c_->compiled().backend());
  }
  const std::string &warnings() const { return warnings_; }

private:
  std::ostringstream out_; // the stages' diagnostics (outlives c_)
  std::unique_ptr<driver::Compilation> c_;
  std::string warnings_;
};

/// The `--analyze --json` report of a model, as JSON text, and whether the
/// analysis succeeded (the report is filled either way, as the command's).
py::tuple analyze(const CompileArgs &args) {
  std::ostringstream out;
  driver::Compilation c(compileRequest(args, true), out);
  bool ok;
  std::string json;
  {
    py::gil_scoped_release release;
    if (!c.parse())
      throw StageError{driver::errorKindOfExitCode(c.exitCode()), out.str()};
    ok = c.analyze();
    json = passes::analysisToJson(c.analysis()).dump();
  }
  return py::make_tuple(json, ok, out.str());
}

CompileArgs compileArgs(std::string path, std::string model,
                        std::string method, std::vector<std::string> outputs,
                        std::string jit, std::vector<std::string> overrides,
                        std::string cacheDir) {
  return CompileArgs{std::move(path),      std::move(model),
                     std::move(method),    std::move(jit),
                     std::move(cacheDir),  std::move(outputs),
                     std::move(overrides)};
}

} // namespace

PYBIND11_MODULE(_ldaec, m) {
  m.doc() = "ldaec's compiler and runtime (use the package ldaec)";

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p)
        std::rethrow_exception(p);
    } catch (const StageError &e) {
      static const char *classes[] = {"ModelError", "ModelError",
                                      "UsageError", "SimulationError"};
      const char *cls = classes[driver::exitCode(e.kind)];
      py::object type = py::module_::import("ldaec.errors").attr(cls);
      py::object error = type(py::str(e.text));
      error.attr("kind") = driver::errorKindName(e.kind);
      PyErr_SetObject(type.ptr(), error.ptr());
    }
  });

  py::class_<Result>(m, "Result")
      .def_property_readonly("data", &Result::data)
      .def_property_readonly("columns", &Result::columns)
      .def_property_readonly("params", &Result::params)
      .def_property_readonly("stats", &Result::stats)
      .def_property_readonly("status",
                             [](const Result &r) { return r.raw().status; })
      .def_property_readonly("failure",
                             [](const Result &r) { return r.raw().failure; })
      .def_property_readonly("model",
                             [](const Result &r) { return r.raw().model; })
      .def_property_readonly("log", &Result::log)
      .def_property_readonly("diagnostics", &Result::diagnostics)
      .def("write", &Result::write, py::arg("path"), py::arg("format") = "");

  py::class_<Model>(m, "Model")
      .def(py::init([](std::string path, std::string model, std::string method,
                       std::vector<std::string> outputs, std::string jit,
                       std::vector<std::string> overrides,
                       std::string cacheDir) {
             return std::make_unique<Model>(compileArgs(
                 std::move(path), std::move(model), std::move(method),
                 std::move(outputs), std::move(jit), std::move(overrides),
                 std::move(cacheDir)));
           }),
           py::arg("path"), py::arg("model") = "", py::arg("method") = "dd",
           py::arg("outputs") = std::vector<std::string>{},
           py::arg("jit") = "auto",
           py::arg("overrides") = std::vector<std::string>{},
           py::arg("cache_dir") = "")
      .def(
          "simulate",
          [](Model &self, std::optional<double> start,
             std::optional<double> stop, std::optional<double> rtol,
             std::optional<double> atol, std::optional<double> interval,
             bool everyStep, std::vector<double> times,
             std::vector<std::string> outputs, std::string integrator,
             std::optional<bool> algebraicErrorTest,
             std::map<std::string, double> params,
             std::map<std::string, double> starts) {
            return self.simulate(driver::RunRequest{
                .start = start,
                .stop = stop,
                .rtol = rtol,
                .atol = atol,
                .interval = interval,
                .everyStep = everyStep,
                .times = std::move(times),
                .outputs = std::move(outputs),
                .integrator =
                    usable(driver::parseIntegratorOption(integrator)),
                .algebraicErrorTest = driver::switchChoice(algebraicErrorTest),
                .params = std::move(params),
                .starts = std::move(starts)});
          },
          py::arg("start") = py::none(), py::arg("stop") = py::none(),
          py::arg("rtol") = py::none(), py::arg("atol") = py::none(),
          py::arg("interval") = py::none(), py::arg("every_step") = false,
          py::arg("times") = std::vector<double>{},
          py::arg("outputs") = std::vector<std::string>{},
          py::arg("integrator") = "auto",
          py::arg("algebraic_error_test") = py::none(),
          py::arg("params") = std::map<std::string, double>{},
          py::arg("starts") = std::map<std::string, double>{})
      .def_property_readonly("parameters", &Model::parameters)
      .def_property_readonly("structural", &Model::structural)
      .def_property_readonly("unknowns", &Model::unknowns)
      .def_property_readonly("starts", &Model::starts)
      .def_property_readonly("output_names", &Model::outputNames)
      .def("expand_outputs", &Model::expandOutputs, py::arg("patterns"))
      .def_property_readonly("name", &Model::name)
      .def_property_readonly("compile_seconds", &Model::compileSeconds)
      .def_property_readonly("backend", &Model::backend)
      .def_property_readonly("warnings", &Model::warnings);

  m.def(
      "analyze",
      [](std::string path, std::string model, std::string method,
         std::vector<std::string> overrides) {
        return analyze(compileArgs(std::move(path), std::move(model),
                                   std::move(method), {}, "auto",
                                   std::move(overrides), ""));
      },
      py::arg("path"), py::arg("model") = "", py::arg("method") = "dd",
      py::arg("overrides") = std::vector<std::string>{});

  m.def("default_cache_dir", &driver::defaultCacheDir);
}
