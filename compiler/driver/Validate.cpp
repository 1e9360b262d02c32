// Command-line checks (see Validate.h). They run before the model is read
// (or, for --outputs, right after it is flattened) so that a typo costs no
// compile time and never leaves a half-written result behind.
#include "Validate.h"

#include "frontend/Frontend.h"
#include "passes/Pipeline.h"
#include "ldae/ResultWriter.h"
#include "ldae/Sweep.h"
#include "ldae/Simulation.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <set>
#include <cerrno>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

namespace ldae::driver {

namespace {

/// Largest magnitude of a start or stop time: stop - start and the output
/// grid then never overflow a double.
constexpr double kMaxTime = 1e300;

/// What `st_mode` is, for "it is a directory, not a regular file".
const char *fileKind(mode_t mode) {
  if (S_ISDIR(mode))
    return "a directory";
  if (S_ISCHR(mode))
    return "a character device";
  if (S_ISBLK(mode))
    return "a block device";
  if (S_ISFIFO(mode))
    return "a pipe";
  if (S_ISSOCK(mode))
    return "a socket";
  return "a special file";
}

bool checkInput(const std::string &path, DiagnosticEngine &diags) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) {
    diags.report(DiagId::ErrCannotReadFile, SourceLoc{}, {path});
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    diags.report(DiagId::ErrInputNotRegular, SourceLoc{},
                 {path, fileKind(st.st_mode)});
    return false;
  }
  return true;
}

/// The file can be written, found before any work: its directory exists
/// and can be written, the file, if there, is no directory and can be
/// written. (A run of minutes, or a sweep's results, were lost to an -o
/// found unwritable only at the end.)
bool checkOutputDir(const std::string &path, const std::string &what,
                    DiagnosticEngine &diags) {
  if (path.empty() || path == "-")
    return true;
  size_t slash = path.rfind('/');
  std::string dir = slash == std::string::npos ? "."
                    : slash == 0               ? "/"
                                               : path.substr(0, slash);
  struct stat st;
  if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    diags.report(DiagId::ErrNoSuchDirectory, SourceLoc{}, {path, what, dir});
    return false;
  }
  const bool exists = stat(path.c_str(), &st) == 0;
  std::string why;
  if (exists && S_ISDIR(st.st_mode))
    why = "it is a directory";
  else if (exists && access(path.c_str(), W_OK) != 0)
    why = std::string("it is not writable (") + std::strerror(errno) + ")";
  else if (!exists && access(dir.c_str(), W_OK | X_OK) != 0)
    why = "the directory '" + dir + "' is not writable (" +
          std::strerror(errno) + ")";
  if (why.empty())
    return true;
  diags.report(DiagId::ErrCannotWriteOutput, SourceLoc{}, {path, what, why});
  return false;
}

bool checkParam(const std::string &p, DiagnosticEngine &diags) {
  frontend::ParamOverride o = frontend::parseParamOverride(p);
  if (o.name.empty()) {
    diags.report(DiagId::ErrBadOverride, SourceLoc{}, {p});
    return false;
  }
  if (!o.value) {
    diags.report(DiagId::ErrParamNotNumber, SourceLoc{}, {p, o.text});
    return false;
  }
  return true;
}

bool endsWith(const std::string &s, const std::string &tail) {
  return s.size() >= tail.size() &&
         s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string text(double v) { return fmt::format("{}", v); }

/// A number option: finite, within the time range when `isTime`, positive
/// when `positive`.
bool checkNumber(const char *option, const std::optional<double> &v,
                 bool isTime, bool positive, DiagnosticEngine &diags) {
  if (!v)
    return true;
  if (!std::isfinite(*v)) {
    diags.report(DiagId::ErrOptionNotFinite, SourceLoc{}, {option, text(*v)});
    return false;
  }
  if (isTime && std::fabs(*v) > kMaxTime) {
    diags.report(DiagId::ErrTimeOutOfRange, SourceLoc{}, {option, text(*v)});
    return false;
  }
  if (positive && !(*v > 0)) {
    diags.report(DiagId::ErrOptionNotPositive, SourceLoc{},
                 {option, text(*v)});
    return false;
  }
  return true;
}

bool checkTimes(const Options &o, DiagnosticEngine &diags) {
  bool ok = checkNumber("--start", o.run.start, true, false, diags) &
            checkNumber("--stop", o.run.stop, true, false, diags) &
            checkNumber("--rtol", o.run.rtol, false, true, diags) &
            checkNumber("--atol", o.run.atol, false, true, diags) &
            checkNumber("--interval", o.run.interval, false, true, diags);
  for (size_t i = 0; ok && i < o.run.times.size(); ++i) {
    ok = checkNumber("--output-times", o.run.times[i], true, false, diags);
    if (ok && i > 0 && !(o.run.times[i] > o.run.times[i - 1])) {
      diags.report(DiagId::ErrOutputTimesOrder, SourceLoc{},
                   {text(o.run.times[i]), text(o.run.times[i - 1])});
      ok = false;
    }
  }
  if (!ok)
    return false;
  // The model's experiment annotation may set what is not given here; the
  // runtime checks the resolved values again.
  double start = o.run.start.value_or(0.0);
  if (o.run.stop && *o.run.stop < start) {
    diags.report(DiagId::ErrStopBeforeStart, SourceLoc{},
                 {text(*o.run.stop), text(start)});
    return false;
  }
  if (o.run.stop && o.run.interval && *o.run.stop > start &&
      runtime::outputRows(start, *o.run.stop, *o.run.interval) >
          runtime::kMaxOutputRows) {
    diags.report(
        DiagId::ErrTooManyRows, SourceLoc{},
        {runtime::tooManyRowsMessage(start, *o.run.stop, *o.run.interval)});
    return false;
  }
  return true;
}

/// Options that only do something in one mode.
struct ModeOption {
  const char *name; // as CLI11 knows it (count())
  const char *shown;
  bool simulate, emit, analyze;
};

bool checkModes(const CLI::App &app, const Options &o,
                DiagnosticEngine &diags) {
  bool ok = true;
  if (o.simulate && o.analyze) {
    diags.report(DiagId::ErrModesConflict, SourceLoc{},
                 {"--analyze", "--simulate"});
    return false;
  }
  if (o.emit != EmitKind::None && (o.simulate || o.analyze)) {
    diags.report(DiagId::ErrModesConflict, SourceLoc{},
                 {"--emit", o.simulate ? "--simulate" : "--analyze"});
    return false;
  }
  static const ModeOption table[] = {
      {"--start", "--start", true, false, false},
      {"--stop", "--stop", true, false, false},
      {"--rtol", "--rtol", true, false, false},
      {"--atol", "--atol", true, false, false},
      {"--interval", "--interval", true, false, false},
      {"--every-step", "--every-step", true, false, false},
      {"--output-times", "--output-times", true, false, false},
      {"--algebraic-error-test", "--algebraic-error-test", true, false, false},
      {"--integrator", "--integrator", true, false, false},
      {"--plot", "--plot", true, false, false},
      {"--stats", "--stats", true, false, false},
      {"--compile-only", "--compile-only", true, false, false},
      {"--jit", "--jit", true, false, false},
      {"--format", "--format", true, false, false},
      {"--sweep", "--sweep", true, false, false},
      {"--no-cache", "--no-cache", true, false, false},
      {"--outputs", "--outputs", true, true, false},
      {"-o", "-o", true, true, false},
  };
  bool emitsModel = o.emit != EmitKind::None && o.emit != EmitKind::Flat;
  for (const ModeOption &m : table) {
    if (app.count(m.name) == 0)
      continue;
    bool used =
        (m.simulate && o.simulate) ||
        (m.emit &&
         (std::string(m.name) == "-o" ? o.emit != EmitKind::None : emitsModel));
    if (used)
      continue;
    std::string modes = m.emit ? (std::string(m.name) == "-o"
                                      ? "'--simulate' or '--emit'"
                                      : "'--simulate' or '--emit "
                                        "reduced|llvm|c'")
                               : "'--simulate'";
    diags.report(DiagId::ErrOptionNeedsMode, SourceLoc{}, {m.shown, modes});
    ok = false;
  }
  if (o.emit == EmitKind::Flat)
    // The flat model is printed before any pass runs.
    for (const char *name : {"--print-after", "--method"})
      if (app.count(name)) {
        diags.report(DiagId::ErrOptionNoEffectWith, SourceLoc{},
                     {name, "'--emit flat'"});
        ok = false;
      }
  if (o.json && !o.analyze) {
    diags.report(DiagId::ErrOptionNeedsMode, SourceLoc{},
                 {"--json", "'--analyze'"});
    ok = false;
  }
  if (app.count("--jobs") && o.sweep.empty()) {
    diags.report(DiagId::ErrOptionNeedsMode, SourceLoc{},
                 {"--jobs", "'--sweep'"});
    ok = false;
  }
  if (!o.sweep.empty() && !o.plotFile.empty()) {
    diags.report(DiagId::ErrModesConflict, SourceLoc{}, {"--sweep", "--plot"});
    ok = false;
  }
  if (o.emitMain && o.emit != EmitKind::C) {
    diags.report(DiagId::ErrOptionNeedsMode, SourceLoc{},
                 {"--main", "'--emit c'"});
    ok = false;
  }
  return ok;
}

bool checkPasses(const Options &o, DiagnosticEngine &diags) {
  std::set<std::string> names;
  for (const passes::PassInfo &p : passes::passList())
    names.insert(p.name);
  bool ok = true;
  for (const std::string &name : o.printAfter)
    if (!names.count(name)) {
      diags.report(DiagId::ErrUnknownPass, SourceLoc{},
                   {name, passes::passNames()});
      ok = false;
    }
  return ok;
}

/// The result format: csv or mat, by --format or -o's extension; a .mat
/// file needs a file (not standard output).
bool checkResultFile(const Options &o, DiagnosticEngine &diags) {
  if (!o.simulate)
    return true;
  Expected<runtime::ResultFormat> format =
      runtime::resultFormat(o.outputFile, o.format);
  if (!format) {
    diags.report(DiagId::ErrResultFormat, SourceLoc{},
                 {o.outputFile, format.error()});
    return false;
  }
  if (*format == runtime::ResultFormat::Mat &&
      (o.outputFile.empty() || o.outputFile == "-")) {
    diags.report(DiagId::ErrResultFormat, SourceLoc{},
                 {"-", "a .mat file cannot go to standard output; name it "
                       "with -o run.mat"});
    return false;
  }
  // A .mat file is checked by its size once written (MatFile::close):
  // a device or a pipe cannot be, so it is refused here.
  struct stat st;
  if (*format == runtime::ResultFormat::Mat && o.outputFile != "/dev/null" &&
      stat(o.outputFile.c_str(), &st) == 0 && !S_ISREG(st.st_mode) &&
      !S_ISDIR(st.st_mode)) {
    diags.report(DiagId::ErrResultFormat, SourceLoc{},
                 {o.outputFile, std::string("a .mat result goes to a regular "
                                            "file, not to ") +
                                    fileKind(st.st_mode)});
    return false;
  }
  return true;
}

} // namespace

bool isClassName(const std::string &input) {
  struct stat st;
  if (input.empty() || stat(input.c_str(), &st) == 0 ||
      !(std::isalpha(static_cast<unsigned char>(input[0])) || input[0] == '_'))
    return false;
  for (char c : input)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '.')
      return false;
  auto endsWith = [&](const std::string &suffix) {
    return input.size() >= suffix.size() &&
           input.compare(input.size() - suffix.size(), suffix.size(),
                         suffix) == 0;
  };
  return input.back() != '.' && input.find("..") == std::string::npos &&
         !endsWith(".lsd") && !endsWith(".mo");
}


// Commas inside brackets belong to a subscript: `u[2,2],x` is two names.
std::vector<std::string> splitOutputs(const std::string &list) {
  std::vector<std::string> out;
  std::string name;
  int depth = 0;
  for (char ch : list) {
    depth += ch == '[' ? 1 : ch == ']' && depth > 0 ? -1 : 0;
    if (ch == ',' && depth == 0) {
      if (!name.empty())
        out.push_back(std::move(name));
      name.clear();
      continue;
    }
    name += ch;
  }
  if (!name.empty())
    out.push_back(std::move(name));
  return out;
}

bool checkCommandLine(const CLI::App &app, const Options &o,
                      DiagnosticEngine &diags) {
  // Cheapest first; every problem is reported, not only the first.
  bool ok = checkModes(app, o, diags);
  ok &= checkTimes(o, diags);
  for (const std::string &p : o.paramOverrides)
    ok &= checkParam(p, diags);
  ok &= checkPasses(o, diags);
  for (const char *opt : {"-o", "--plot"})
    if (app.count(opt) > 0 &&
        (std::string(opt) == "-o" ? o.outputFile : o.plotFile).empty()) {
      diags.report(DiagId::ErrEmptyOutputName, SourceLoc{}, {opt});
      ok = false;
    }
  ok &= checkOutputDir(o.outputFile, "-o", diags);
  ok &= checkOutputDir(o.plotFile, "--plot", diags);
  if (!o.plotFile.empty() && !endsWith(o.plotFile, ".svg") &&
      !endsWith(o.plotFile, ".png") && !endsWith(o.plotFile, ".pdf")) {
    diags.report(DiagId::ErrPlotExtension, SourceLoc{}, {o.plotFile});
    ok = false;
  }
  for (const std::string &list : o.overrides)
    for (const std::string &p : splitOutputs(list))
      ok &= checkParam(p, diags);
  ok &= checkResultFile(o, diags);
  std::vector<runtime::SweepAxis> axes;
  for (const std::string &spec : o.sweep)
    if (Expected<runtime::SweepAxis> axis = runtime::parseSweepAxis(spec);
        !axis) {
      diags.report(DiagId::ErrBadSweep, SourceLoc{}, {spec, axis.error()});
      ok = false;
    } else {
      axes.push_back(std::move(*axis));
    }
  if (Expected<bool> distinct = runtime::checkSweepAxes(axes); !distinct) {
    diags.report(DiagId::ErrBadSweep, SourceLoc{},
                 {fmt::format("{}", fmt::join(o.sweep, " ")),
                  distinct.error()});
    ok = false;
  }
  // A class on the library path (`Modelica.Blocks.Examples.PID_Controller`)
  // is no file.
  if (isClassName(o.input))
    return ok;
  return checkInput(o.input, diags) && ok;
}

bool hasCommandLineError(const DiagnosticEngine &diags) {
  for (const Diagnostic &d : diags.diagnostics())
    switch (d.id) {
    case DiagId::ErrModelNotFound:
    case DiagId::ErrModelNotFoundSuggest:
    case DiagId::ErrBadOverride:
    case DiagId::ErrUnknownOverride:
    case DiagId::ErrUnknownOverrideSuggest:
    case DiagId::ErrOverrideConstant:
      return true;
    default:
      break;
    }
  return false;
}

} // namespace ldae::driver
