// Plots with gnuplot (see Plot.h, docs/plots.md). planPlot decides the
// panels (pure: unit tests check it without gnuplot); plot writes a data
// file and a script beside the picture, so a user can re-run or edit them,
// and runs gnuplot on the script. No shell is involved: gnuplot is spawned
// with an argument vector, and names reach it only as single-quoted
// gnuplot strings.
#include "ldae/Plot.h"
#include "ldae/ResultWriter.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <fstream>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

namespace ldae::runtime {

/// Runs `argv` (looked up on PATH) without a shell, so no character of a
/// file name is ever interpreted; returns its exit status (-1: could not
/// run) and its stdout and stderr together in `output`.
static int runProgram(const std::vector<std::string> &argv,
                      std::string &output) {
  int fds[2];
  if (pipe(fds) != 0)
    return -1;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null",
                                   O_RDONLY, 0);
  std::vector<char *> args;
  for (const std::string &a : argv)
    args.push_back(const_cast<char *>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (rc != 0) {
    close(fds[0]);
    output = std::strerror(rc);
    return -1;
  }
  char buf[4096];
  ssize_t got;
  while ((got = read(fds[0], buf, sizeof buf)) > 0 ||
         (got < 0 && errno == EINTR))
    if (got > 0)
      output.append(buf, size_t(got));
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Whether this gnuplot knows terminal `name`.
static bool hasTerminal(const std::string &name) {
  std::string text;
  if (runProgram({"gnuplot", "-e", "set terminal"}, text) < 0)
    return false;
  return text.find(" " + name + " ") != std::string::npos;
}

/// `s` as a gnuplot string literal. Single quotes: gnuplot substitutes
/// `command` even inside double-quoted strings, never inside single-quoted
/// ones, where the only escape is '' for '. A line break cannot be written
/// in one (the caller rejects such names).
static std::string gnuplotString(const std::string &s) {
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

namespace {

/// The column's kind; without column info (a result from an older model)
/// only derivatives can be told apart, by name.
ColumnKind kindOf(const SimResult &r, size_t c) {
  if (r.info.size() == r.columns.size())
    return r.info[c].kind;
  return r.columns[c].rfind("der(", 0) == 0 ? ColumnKind::Derivative
                                             : ColumnKind::Continuous;
}

const std::string &unitOf(const SimResult &r, size_t c) {
  static const std::string none;
  return r.info.size() == r.columns.size() ? r.info[c].unit : none;
}

/// Whether the column repeats another one of the result (an alias, or
/// minus one): drawn by default it would only hide the other.
bool isAlias(const SimResult &r, size_t c) {
  return r.info.size() == r.columns.size() && r.info[c].alias != 0;
}

/// The largest finite magnitude of column `c` (0 when none).
double scaleOf(const SimResult &r, size_t c) {
  double s = 0;
  for (const std::vector<double> &row : r.rows)
    if (c < row.size() && std::isfinite(row[c]))
      s = std::max(s, std::fabs(row[c]));
  return s;
}

/// Whether column `c` keeps its first value all run long.
bool isConstant(const SimResult &r, size_t c) {
  for (const std::vector<double> &row : r.rows)
    if (row[c] != r.rows.front()[c])
      return false;
  return true;
}

/// The curves drawn when none are named: the continuous variables (those
/// in `states` when any is), else the discrete ones; those that stay
/// constant go to `constant` unless every one does.
std::vector<int> defaultCurves(const SimResult &r,
                               const std::vector<std::string> &states,
                               std::vector<std::string> &constant) {
  auto isState = [&](size_t c) {
    return std::find(states.begin(), states.end(), r.columns[c]) !=
           states.end();
  };
  bool anyState = false;
  for (size_t c = 1; c < r.columns.size(); ++c)
    anyState = anyState ||
               (kindOf(r, c) == ColumnKind::Continuous && isState(c));
  for (ColumnKind kind : {ColumnKind::Continuous, ColumnKind::Discrete}) {
    std::vector<int> varying, fixed;
    for (size_t c = 1; c < r.columns.size(); ++c)
      if (kindOf(r, c) == kind && !isAlias(r, c) &&
          (!anyState || kind != ColumnKind::Continuous || isState(c)))
        (isConstant(r, c) ? fixed : varying).push_back(int(c));
    if (varying.empty())
      varying.swap(fixed);
    for (int c : fixed)
      constant.push_back(r.columns[c]);
    if (!varying.empty())
      return varying;
  }
  return {};
}

/// The last component of a name: `v` of `C[2].v`.
std::string lastComponent(const std::string &name) {
  size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(dot + 1);
}

/// "v [V]": the name of a single curve, else the last component every
/// curve's name shares, else the unit alone.
std::string axisLabel(const SimResult &r, const PlotPanel &panel) {
  std::string quantity = r.columns[panel.columns.front()];
  if (panel.columns.size() > 1) {
    quantity = lastComponent(quantity);
    for (int c : panel.columns)
      if (lastComponent(r.columns[c]) != quantity)
        quantity.clear();
  }
  if (panel.unit.empty())
    return quantity;
  return quantity.empty() ? "[" + panel.unit + "]"
                          : quantity + " [" + panel.unit + "]";
}

/// Splits the curves of one unit into panels of one scale each (largest
/// scale first), each in model order. Curves that stay zero fit any scale:
/// they join the smallest.
std::vector<std::vector<int>> splitByScale(const SimResult &r,
                                           const std::vector<int> &cols) {
  std::vector<std::pair<double, int>> curves, zeros;
  for (int c : cols)
    (scaleOf(r, c) > 0 ? curves : zeros).push_back({scaleOf(r, c), c});
  std::stable_sort(curves.begin(), curves.end(),
                   [](auto &a, auto &b) { return a.first > b.first; });
  std::vector<std::vector<int>> panels;
  double leader = 0;
  for (auto [scale, c] : curves) {
    if (panels.empty() || scale * kPlotScaleRatio < leader) {
      panels.emplace_back();
      leader = scale;
    }
    panels.back().push_back(c);
  }
  if (!zeros.empty() && panels.empty())
    panels.emplace_back();
  for (auto [scale, c] : zeros)
    panels.back().push_back(c);
  for (std::vector<int> &p : panels)
    std::sort(p.begin(), p.end());
  return panels;
}

} // namespace

std::vector<std::string> unknownNames(const ldae_model &model) {
  std::vector<std::string> names;
  for (int i = 0; i < model.n && model.var_names; ++i)
    if (model.var_names[i])
      names.push_back(model.var_names[i]);
  return names;
}

Expected<PlotPlan> planPlot(const SimResult &result,
                            const std::vector<std::string> &columns,
                            const std::vector<std::string> &states) {
  if (result.rows.empty())
    return Error{"nothing to plot: the run has no rows"};
  PlotPlan plan;
  std::vector<int> cols;
  if (columns.empty()) {
    cols = defaultCurves(result, states, plan.constant);
    if (cols.empty())
      return Error{"nothing to plot: the result has no continuous or "
                   "discrete variable (name the columns to plot)"};
  } else {
    std::vector<std::string> available(result.columns.begin() + 1,
                                       result.columns.end());
    Expected<std::vector<int>> sel = selectColumns(available, columns);
    if (!sel)
      return Error{sel.error()};
    for (int i : *sel)
      if (std::find(cols.begin(), cols.end(), i + 1) == cols.end())
        cols.push_back(i + 1);
  }
  // Units in the order their first curve comes.
  std::vector<std::pair<std::string, std::vector<int>>> groups;
  for (int c : cols) {
    const std::string &unit = unitOf(result, c);
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](auto &e) { return e.first == unit; });
    if (g == groups.end())
      groups.push_back({unit, {c}});
    else
      g->second.push_back(c);
  }
  for (const auto &[unit, members] : groups)
    for (const std::vector<int> &scaled : splitByScale(result, members)) {
      // Over the cap, panels of even sizes: 10 curves are 5 and 5, not 8
      // and 2.
      size_t panels = (scaled.size() + kPlotCurvesPerPanel - 1) /
                      kPlotCurvesPerPanel;
      size_t size = (scaled.size() + panels - 1) / panels;
      for (size_t at = 0; at < scaled.size(); at += size) {
        PlotPanel panel;
        panel.unit = unit;
        panel.columns.assign(scaled.begin() + at,
                             scaled.begin() +
                                 std::min(scaled.size(), at + size));
        panel.label = axisLabel(result, panel);
        plan.panels.push_back(std::move(panel));
      }
    }
  if (plan.panels.size() > kPlotPanels) {
    std::vector<int> dropped;
    for (size_t p = kPlotPanels; p < plan.panels.size(); ++p)
      dropped.insert(dropped.end(), plan.panels[p].columns.begin(),
                     plan.panels[p].columns.end());
    std::sort(dropped.begin(), dropped.end());
    for (int c : dropped)
      plan.leftOut.push_back(result.columns[c]);
    plan.panels.resize(kPlotPanels);
  }
  return plan;
}

namespace {

/// The gnuplot terminal for `path`'s extension and a picture of `panels`
/// panels, or an Error naming the extensions there are.
Expected<std::string> terminalFor(const std::string &path, size_t panels) {
  size_t dot = path.rfind('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  // 280 pixels (2.8 inches) a panel, room for the title.
  int height = int(std::max<size_t>(420, 60 + 280 * panels));
  if (ext == ".png")
    return hasTerminal("pngcairo")
               ? fmt::format("pngcairo size 900,{} font ',10'", height)
               : fmt::format("png size 900,{}", height);
  if (ext == ".svg")
    return fmt::format("svg size 900,{} dynamic font ',10' background "
                       "rgb 'white'",
                       height);
  if (ext == ".pdf") {
    if (!hasTerminal("pdfcairo"))
      return Error{"this gnuplot cannot write PDF (no pdfcairo terminal); "
                   "plot to .png or .svg"};
    return fmt::format("pdfcairo size 9in,{:.1f}in font ',10'",
                       height / 100.0);
  }
  return Error{fmt::format("cannot plot to '{}': the file name must end in "
                           ".svg, .png or .pdf",
                           path)};
}

/// "a, b, c and 4 more": the first names of `names`.
std::string someNames(const std::vector<std::string> &names) {
  const size_t shown = 10;
  std::string text;
  for (size_t i = 0; i < names.size() && i < shown; ++i)
    text += (i ? ", " : "") + names[i];
  if (names.size() > shown)
    text += fmt::format(" and {} more", names.size() - shown);
  return text;
}

/// Says which curves the plot left out and how to draw them.
void noteLeftOut(const PlotPlan &plan, std::ostream &notes) {
  const char *howTo = "name the curves to plot (--outputs) to see them";
  if (!plan.leftOut.empty())
    notes << fmt::format(
        "note: the plot leaves out {} curve{} ({} at most per panel, {} "
        "panels): {}; {}\n",
        plan.leftOut.size(), plan.leftOut.size() == 1 ? "" : "s",
        kPlotCurvesPerPanel, kPlotPanels, someNames(plan.leftOut), howTo);
  if (!plan.constant.empty())
    notes << fmt::format(
        "note: the plot leaves out {} curve{} that stay{} constant: {}; {}\n",
        plan.constant.size(), plan.constant.size() == 1 ? "" : "s",
        plan.constant.size() == 1 ? "s" : "", someNames(plan.constant),
        howTo);
}

/// The gnuplot script drawing `plan` from `dat` (time, then the plan's
/// columns in panel order) into `path`.
std::string plotScript(const SimResult &result, const PlotPlan &plan,
                       const std::string &terminal, const std::string &path,
                       const std::string &dat) {
  std::string s;
  s += "set terminal " + terminal + "\n";
  s += "set output " + gnuplotString(path) + "\n";
  // A line break cannot be written in a gnuplot string.
  std::string title = result.model.empty() ? "ldaec" : result.model;
  std::replace(title.begin(), title.end(), '\n', ' ');
  std::replace(title.begin(), title.end(), '\r', ' ');
  s += fmt::format("set multiplot layout {},1 title {} noenhanced font ',12'\n",
                   plan.panels.size(), gnuplotString(title));
  // Fixed margins line the panels up over one time axis whatever their
  // legends' widths.
  s += "set grid\nset lmargin 12\nset rmargin at screen 0.74\n";
  s += "set key outside right top Left reverse noenhanced\n";
  s += "set format y '%g'\nset format x ''\n";
  int dataColumn = 2;
  for (size_t p = 0; p < plan.panels.size(); ++p) {
    const PlotPanel &panel = plan.panels[p];
    if (p + 1 == plan.panels.size())
      s += "set format x '%g'\nset xlabel 'time [s]'\n";
    s += "set ylabel " + gnuplotString(panel.label) + " noenhanced\n";
    s += "plot ";
    for (size_t i = 0; i < panel.columns.size(); ++i)
      s += fmt::format("{}{} using 1:{} with lines lw 1.5 title {}",
                       i ? ", \\\n     " : "", gnuplotString(dat),
                       dataColumn++,
                       gnuplotString(result.columns[panel.columns[i]]));
    s += "\n";
  }
  s += "unset multiplot\n";
  return s;
}

} // namespace

Expected<bool> plot(const SimResult &result, const std::string &path,
                    const std::vector<std::string> &columns,
                    const std::vector<std::string> &states,
                    std::ostream &notes) {
  Expected<PlotPlan> plan = planPlot(result, columns, states);
  if (!plan)
    return Error{plan.error()};
  Expected<std::string> terminal = terminalFor(path, plan->panels.size());
  if (!terminal)
    return Error{terminal.error()};
  if (path.find_first_of("\n\r") != std::string::npos)
    return Error{"the file name contains a line break"};
  std::vector<int> drawn;
  for (const PlotPanel &panel : plan->panels)
    drawn.insert(drawn.end(), panel.columns.begin(), panel.columns.end());
  for (int c : drawn)
    if (result.columns[c].find_first_of("\n\r") != std::string::npos)
      return Error{fmt::format("the column name '{}' contains a line break",
                               result.columns[c])};
  std::string dat = path + ".dat", script = path + ".gp";
  // Every write checked, with the reason; what could not be written whole
  // is removed (a full disk gave a plot of part of the rows, exit 0).
  auto failed = [&](const std::string &file) {
    int why = errno;
    std::remove(dat.c_str());
    std::remove(script.c_str());
    return Error{fmt::format("cannot write '{}': {}", file,
                             why ? std::strerror(why) : "write error")};
  };
  {
    errno = 0;
    std::ofstream f(dat);
    for (const auto &row : result.rows) {
      std::string line = formatValue(row[0]);
      for (int c : drawn)
        line += " " + formatValue(row[c]);
      f << line << '\n';
    }
    f.close();
    if (!f)
      return failed(dat);
  }
  {
    errno = 0;
    std::ofstream f(script);
    f << plotScript(result, *plan, *terminal, path, dat);
    f.close();
    if (!f)
      return failed(script);
  }
  // "./" keeps a relative name starting with '-' from being an option.
  std::string text;
  int rc = runProgram(
      {"gnuplot", script[0] == '/' ? script : "./" + script}, text);
  if (rc < 0)
    return Error{fmt::format("cannot run gnuplot: {}", text)};
  if (rc != 0)
    return Error{fmt::format("gnuplot failed on '{}': {}", script, text)};
  // gnuplot says nothing when the disk is full under its output.
  struct stat st;
  if (::stat(path.c_str(), &st) != 0 || st.st_size == 0)
    return Error{fmt::format("gnuplot wrote no '{}'{}", path,
                             text.empty() ? "" : ": " + text)};
  noteLeftOut(*plan, notes);
  return true;
}

} // namespace ldae::runtime
