// Plots with gnuplot (see Plot.h). gnuplot reads a data file and a script
// that we write beside the picture, so a user can re-run or edit them. No
// shell is involved: gnuplot is spawned with an argument vector, and names
// reach it only as single-quoted gnuplot strings.
#include "Plot.h"
#include "ResultWriter.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <fstream>
#include <spawn.h>
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

Expected<bool> plot(const SimResult &result, const std::string &path,
                    const std::vector<std::string> &columns) {
  std::string ext = path.size() > 4 ? path.substr(path.size() - 4) : "";
  std::string terminal;
  if (ext == ".svg")
    terminal = "svg size 900,540 dynamic enhanced background rgb 'white'";
  else if (ext == ".png")
    terminal =
        hasTerminal("pngcairo") ? "pngcairo size 900,540" : "png size 900,540";
  else
    return Error{fmt::format("cannot plot to '{}': the file name must end in "
                             ".svg or .png",
                             path)};
  std::vector<std::string> available(result.columns.begin() + 1,
                                     result.columns.end());
  std::vector<int> idx;
  if (columns.empty()) {
    for (size_t i = 0; i < available.size(); ++i)
      idx.push_back(int(i));
  } else {
    auto sel = selectColumns(available, columns);
    if (!sel)
      return Error{sel.error()};
    idx = *sel;
  }
  if (path.find_first_of("\n\r") != std::string::npos)
    return Error{"the file name contains a line break"};
  for (int i : idx)
    if (available[i].find_first_of("\n\r") != std::string::npos)
      return Error{fmt::format("the column name '{}' contains a line break",
                               available[i])};
  std::string dat = path + ".dat", script = path + ".gp";
  {
    std::ofstream f(dat);
    if (!f)
      return Error{fmt::format("cannot write '{}'", dat)};
    for (const auto &row : result.rows) {
      std::string line;
      for (size_t c = 0; c < row.size(); ++c)
        line += (c ? " " : "") + formatValue(row[c]);
      f << line << '\n';
    }
  }
  {
    std::ofstream f(script);
    if (!f)
      return Error{fmt::format("cannot write '{}'", script)};
    f << "set terminal " << terminal << "\n";
    f << "set output " << gnuplotString(path) << "\n";
    f << "set xlabel 'time'\nset grid\nset key outside right\n";
    f << "set datafile separator ' '\n";
    f << "plot ";
    for (size_t i = 0; i < idx.size(); ++i)
      f << (i ? ", \\\n     " : "") << gnuplotString(dat)
        << " using 1:" << idx[i] + 2 << " with lines title "
        << gnuplotString(available[idx[i]]) << " noenhanced";
    f << "\n";
  }
  // "./" keeps a relative name starting with '-' from being an option.
  std::string text;
  int rc = runProgram(
      {"gnuplot", script[0] == '/' ? script : "./" + script}, text);
  if (rc < 0)
    return Error{fmt::format("cannot run gnuplot: {}", text)};
  if (rc != 0)
    return Error{fmt::format("gnuplot failed on '{}': {}", script, text)};
  return true;
}

} // namespace ldae::runtime
