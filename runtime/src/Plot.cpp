// Plots with gnuplot (see Plot.h). gnuplot reads a data file and a script
// that we write beside the picture, so a user can re-run or edit them.
#include "Plot.h"
#include "ResultWriter.h"

#include <cstdio>
#include <fmt/format.h>
#include <fstream>

namespace ldae::runtime {

/// Whether this gnuplot knows terminal `name` (asked once per name).
static bool hasTerminal(const std::string &name) {
  FILE *p = popen("gnuplot -e 'set terminal' 2>&1", "r");
  if (!p)
    return false;
  std::string text;
  char buf[4096];
  size_t got;
  while ((got = fread(buf, 1, sizeof buf, p)) > 0)
    text.append(buf, got);
  pclose(p);
  return text.find(" " + name + " ") != std::string::npos;
}

static std::string gnuplotString(const std::string &s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      q += '\\';
    q += c;
  }
  return q + "\"";
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
  std::string cmd = "gnuplot " + gnuplotString(script) + " 2>&1";
  FILE *p = popen(cmd.c_str(), "r");
  if (!p)
    return Error{"cannot run gnuplot"};
  std::string text;
  char buf[1024];
  size_t got;
  while ((got = fread(buf, 1, sizeof buf, p)) > 0)
    text.append(buf, got);
  int rc = pclose(p);
  if (rc != 0)
    return Error{fmt::format("gnuplot failed on '{}': {}", script, text)};
  return true;
}

} // namespace ldae::runtime
