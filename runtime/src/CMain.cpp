// The C entry point ldae_main (ldae/run.h): the main of an emitted
// program. It owns only what the program's command line adds to
// `ldaec --simulate`: parsing it, re-evaluating what a changed parameter
// binds (the JIT path recompiles instead), and exit codes. The run itself
// is runtime::simulate and writeCsv, so both programs compute and write
// the same thing. Built into libldaert (runtime/CMakeLists.txt), which
// exports this one symbol.
#include "ldae/run.h"

#include "ResultWriter.h"
#include "ldae/Simulation.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <new>
#include <unistd.h>

namespace ldae::runtime {

namespace {

/// Exit codes of the program (docs/embedding-c.md).
enum ExitCode { kOk = 0, kInternal = 1, kBadCommandLine = 2, kFailed = 3 };

/// One parsed command line.
struct Args {
  SimOptions sim;
  std::string outPath = "-";
  bool stats = false;
  /// Parameter values given with --param, by index.
  std::vector<std::pair<int, double>> params;
};

int fail(int code, const std::string &message) {
  std::cerr << "error: " << message << "\n";
  return code;
}

bool structural(const ldae_bindings &b, int k) {
  return b.structural && b.structural[k];
}

void printUsage(const ldae_model &m, const ldae_bindings &b) {
  std::cout << fmt::format(
      "Simulates model {} with the ldaec runtime (as ldaec --simulate) and "
      "writes CSV.\n"
      "Usage: ./model [--start T0] [--stop T1] [--interval H] [--rtol R] "
      "[--atol A]\n"
      "               [--integrator auto|ida|cvode|cvode-bdf|cvode-adams] "
      "[--stats]\n"
      "               [--algebraic-error-test on|off|auto] "
      "[--param NAME=VALUE]... [-o FILE]\n"
      "               [--no-progress] [--help]\n"
      "Exit codes: 0 success, 1 internal error, 2 bad command line, "
      "3 numerical failure\n"
      "(the rows up to it are written).\n",
      m.name ? m.name : "?");
  if (m.n_params > 0)
    std::cout << "Parameters:\n";
  for (int k = 0; k < m.n_params; ++k)
    std::cout << "  " << m.param_names[k] << " = "
              << formatValue(m.param_values[k])
              << (structural(b, k) ? " (fixes the structure)" : "") << "\n";
}

/// A whole-string finite number, or a message (exit 2).
bool parseNumber(const char *opt, const char *text, double &x) {
  char *end = nullptr;
  x = std::strtod(text, &end);
  if (end != text && *end == '\0' && std::isfinite(x))
    return true;
  fail(kBadCommandLine,
       fmt::format("{}: '{}' is not a finite number", opt, text));
  return false;
}

/// NAME=VALUE of --param: a known, non-structural parameter.
bool parseParam(const ldae_model &m, const ldae_bindings &b, const char *text,
                Args &args) {
  const char *eq = std::strchr(text, '=');
  if (!eq) {
    fail(kBadCommandLine,
         fmt::format("--param '{}': expected NAME=VALUE", text));
    return false;
  }
  std::string name(text, eq);
  std::vector<std::string> names(m.param_names, m.param_names + m.n_params);
  int k = 0;
  while (k < m.n_params && names[k] != name)
    ++k;
  if (k == m.n_params) {
    std::vector<std::string> close = closeNames(names, name, 3);
    std::string hint;
    for (size_t i = 0; i < close.size(); ++i)
      hint += fmt::format("{}'{}'", i ? ", " : "; did you mean ", close[i]);
    fail(kBadCommandLine,
         fmt::format("--param: the model has no parameter '{}'{} (see --help)",
                     name, hint));
    return false;
  }
  if (structural(b, k)) {
    fail(kBadCommandLine,
         fmt::format("--param: parameter '{}' fixes the model's structure "
                     "(an array size, a branch or a subscript); recompile "
                     "with ldaec --param {}",
                     name, text));
    return false;
  }
  double v;
  if (!parseNumber("--param", eq + 1, v))
    return false;
  args.params.emplace_back(k, v);
  return true;
}

bool parseIntegratorOption(const char *text, IntegratorChoice &choice) {
  if (auto c = ldae::runtime::parseIntegrator(text)) {
    choice = *c;
    return true;
  }
  fail(kBadCommandLine,
       fmt::format("--integrator: '{}' is not one of auto, ida, cvode, "
                   "cvode-bdf, cvode-adams",
                   text));
  return false;
}

/// on, off or auto (unset: the runtime's default rule).
bool parseOnOffAuto(const char *opt, const char *text,
                    std::optional<bool> &value) {
  std::string s = text;
  if (s == "on" || s == "off" || s == "auto") {
    value = s == "auto" ? std::nullopt : std::optional<bool>(s == "on");
    return true;
  }
  fail(kBadCommandLine,
       fmt::format("{}: '{}' is not one of on, off, auto", opt, text));
  return false;
}

/// Fills `args` from argv; false after printing why (exit 2).
bool parseArgs(const ldae_model &m, const ldae_bindings &b, int argc,
               char **argv, Args &args) {
  args.sim.progress = isatty(STDERR_FILENO);
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--stats") {
      args.stats = true;
      continue;
    }
    if (a == "--no-progress") {
      args.sim.progress = false;
      continue;
    }
    std::optional<double> *number = a == "--start"      ? &args.sim.start
                                     : a == "--stop"     ? &args.sim.stop
                                     : a == "--interval" ? &args.sim.interval
                                     : a == "--rtol"     ? &args.sim.rtol
                                     : a == "--atol"     ? &args.sim.atol
                                                         : nullptr;
    if (!number && a != "-o" && a != "--param" && a != "--integrator" &&
        a != "--algebraic-error-test") {
      fail(kBadCommandLine,
           fmt::format("unknown option '{}' (see --help)", a));
      return false;
    }
    if (i + 1 == argc) {
      fail(kBadCommandLine, fmt::format("option '{}' needs a value", a));
      return false;
    }
    const char *v = argv[++i];
    double x;
    bool ok = true;
    if (number) {
      ok = parseNumber(a.c_str(), v, x);
      *number = x;
    } else if (a == "-o") {
      args.outPath = v;
    } else if (a == "--integrator") {
      ok = parseIntegratorOption(v, args.sim.integrator);
    } else if (a == "--algebraic-error-test") {
      ok = parseOnOffAuto(a.c_str(), v, args.sim.algebraicErrorTest);
    } else {
      ok = parseParam(m, b, v, args);
    }
    if (!ok)
      return false;
  }
  return true;
}

/// Re-evaluates what reads a changed parameter, as recompiling with
/// `ldaec --param` would: the bound parameters not given on the command
/// line (one pass per level of a chain of bindings), then the start values.
/// Returns the message of a binding outside its domain, or "".
std::string rebind(const ldae_model &m, const ldae_bindings &b, double t0,
                   const std::vector<std::pair<int, double>> &given,
                   std::vector<double> &p, std::vector<double> &y,
                   const std::vector<double> &yp) {
  std::vector<char> isGiven(m.n_params, 0);
  for (auto [k, v] : given) {
    p[k] = v;
    isGiven[k] = 1;
  }
  if (!b.bind || b.n_bound_params + b.n_bound_starts == 0)
    return "";
  std::vector<double> out(b.n_bound_params + b.n_bound_starts);
  for (int pass = 0; pass <= b.bind_passes; ++pass) {
    int rc = b.bind(t0, y.data(), yp.data(), p.data(), out.data());
    if (rc > 0) {
      int row = rc - 1;
      return row < b.n_bound_params
                 ? fmt::format("the binding of parameter '{}' is outside its "
                               "domain",
                               m.param_names[b.bound_params[row]])
                 : fmt::format("the start value of '{}' is outside its "
                               "domain",
                               m.var_names[b.bound_starts[row -
                                                          b.n_bound_params]]);
    }
    if (rc != 0)
      return "the parameter bindings could not be evaluated";
    if (pass == b.bind_passes)
      break;
    for (int j = 0; j < b.n_bound_params; ++j)
      if (!isGiven[b.bound_params[j]])
        p[b.bound_params[j]] = out[j];
  }
  for (int j = 0; j < b.n_bound_starts; ++j)
    y[b.bound_starts[j]] = out[b.n_bound_params + j];
  return "";
}

/// The columns of `ldaec --simulate` by default: the model's outputs but
/// the derivatives (empty: every unknown).
std::vector<std::string> defaultOutputs(const ldae_model &m) {
  std::vector<std::string> names;
  for (int i = 0; i < m.n_outputs; ++i)
    if (std::strncmp(m.output_names[i], "der(", 4) != 0)
      names.push_back(m.output_names[i]);
  return names;
}

int run(const ldae_model &m, const ldae_bindings &b, int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      printUsage(m, b);
      return kOk;
    }
  Args args;
  if (!parseArgs(m, b, argc, argv, args))
    return kBadCommandLine;
  std::ofstream file;
  if (args.outPath != "-") {
    file.open(args.outPath);
    if (!file)
      return fail(kBadCommandLine,
                  fmt::format("cannot write '{}'", args.outPath));
  }

  // The model with the changed parameters and start values: the runtime
  // reads both from the struct.
  std::vector<double> p(m.param_values, m.param_values + m.n_params);
  std::vector<double> y(m.start_y, m.start_y + m.n);
  std::vector<double> yp(m.start_yp, m.start_yp + m.n);
  double t0 = args.sim.start      ? *args.sim.start
              : std::isnan(m.start_time) ? 0.0
                                         : m.start_time;
  std::string bad = rebind(m, b, t0, args.params, p, y, yp);
  if (!bad.empty())
    return fail(kFailed, bad);
  ldae_model changed = m;
  changed.param_values = p.data();
  changed.start_y = y.data();

  args.sim.outputs = defaultOutputs(m);
  args.sim.log = &std::cerr;
  Expected<SimResult> result = simulate(changed, args.sim);
  if (!result)
    return fail(kBadCommandLine, result.error());
  int rc = kOk;
  if (result->status != 0) {
    fail(kFailed, result->failure);
    rc = kFailed;
  }
  std::ostream &out = args.outPath == "-" ? std::cout : file;
  writeCsv(*result, out);
  if (!out)
    return fail(kInternal, fmt::format("cannot write '{}'", args.outPath));
  if (args.stats)
    printStats(result->stats, std::cerr);
  return rc;
}

} // namespace

} // namespace ldae::runtime

extern "C" __attribute__((visibility("default"))) int
ldae_main(const ldae_model *model, const ldae_bindings *bindings, int argc,
          char **argv) {
  static const ldae_bindings none = {};
  // Nothing may leave a C caller as an exception (C has no unwinding).
  try {
    return ldae::runtime::run(*model, bindings ? *bindings : none, argc, argv);
  } catch (const std::bad_alloc &) {
    return ldae::runtime::fail(ldae::runtime::kInternal, "out of memory");
  } catch (const std::exception &e) {
    return ldae::runtime::fail(ldae::runtime::kInternal,
                               std::string("internal error: ") + e.what());
  }
}
