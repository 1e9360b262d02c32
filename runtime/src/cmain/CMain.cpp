// The C entry point ldae_main (ldae/run.h): the main of an emitted
// program. It owns only what the program's command line adds to
// `ldaec --simulate`: parsing it and exit codes. The run itself is
// runtime::simulate (which also re-evaluates what a changed parameter
// binds, Rebind.h) and writeResult, so both programs compute and write the
// same thing. Built into libldaert (runtime/CMakeLists.txt), which
// exports this one symbol.
#include "ldae/run.h"

#include "ldae/Rebind.h"
#include "ldae/ResultWriter.h"
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
};

int fail(int code, const std::string &message) {
  std::cerr << "error: " << message << "\n";
  return code;
}

bool structural(const ldae_model &m, int k) {
  return m.param_structural && m.param_structural[k];
}

void printUsage(const ldae_model &m) {
  std::cout << fmt::format(
      "Simulates model {} with the ldaec runtime (as ldaec --simulate) and "
      "writes CSV\n"
      "(a .mat file in OpenModelica's layout with -o FILE.mat).\n"
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
              << (!structural(m, k)                           ? ""
                  : m.param_structural[k] == kConstantParameter ? " (constant)"
                                                                : " (fixes the structure)")
              << "\n";
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
bool parseParam(const ldae_model &m, const char *text, Args &args) {
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
  if (structural(m, k)) {
    bool constant = m.param_structural[k] == kConstantParameter;
    fail(kBadCommandLine,
         fmt::format("--param: {}{}{}", structuralParameterMessage(m, k),
                     constant ? "" : "; recompile with ldaec --param ",
                     constant ? "" : text));
    return false;
  }
  double v;
  if (!parseNumber("--param", eq + 1, v))
    return false;
  args.sim.params[name] = v;
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
bool parseArgs(const ldae_model &m, int argc, char **argv, Args &args) {
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
      ok = parseParam(m, v, args);
    }
    if (!ok)
      return false;
  }
  return true;
}

int run(const ldae_model &m, int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      printUsage(m);
      return kOk;
    }
  Args args;
  if (!parseArgs(m, argc, argv, args))
    return kBadCommandLine;
  Expected<ResultFormat> format = resultFormat(args.outPath);
  if (args.outPath != "-" && !std::ofstream(args.outPath))
    return fail(kBadCommandLine,
                fmt::format("cannot write '{}'", args.outPath));

  args.sim.log = &std::cerr;
  // The rows go to the file as the run produces them (docs/results.md).
  auto file = ResultFile::open(args.outPath, *format);
  if (!file)
    return fail(kBadCommandLine, file.error());
  args.sim.rowSink = file->get();
  Expected<SimResult> result = simulate(m, args.sim);
  if (!result)
    return fail(kBadCommandLine, result.error());
  int rc = kOk;
  if (result->status != 0) {
    fail(kFailed, result->failure);
    rc = kFailed;
  }
  Expected<bool> written = (*file)->finish(*result);
  if (written && !result->writeFailure.empty())
    written = Error{result->writeFailure};
  if (!written)
    return fail(kInternal, written.error());
  if (args.stats)
    printStats(result->stats, std::cerr);
  return rc;
}

} // namespace

} // namespace ldae::runtime

extern "C" __attribute__((visibility("default"))) int
ldae_main(const ldae_model *model, int argc, char **argv) {
  // Nothing may leave a C caller as an exception (C has no unwinding).
  try {
    return ldae::runtime::run(*model, argc, argv);
  } catch (const std::bad_alloc &) {
    return ldae::runtime::fail(ldae::runtime::kInternal, "out of memory");
  } catch (const std::exception &e) {
    return ldae::runtime::fail(ldae::runtime::kInternal,
                               std::string("internal error: ") + e.what());
  }
}
