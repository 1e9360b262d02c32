// CSV output and column selection by name (see ResultWriter.h).
#include "ResultWriter.h"
#include "support/EditDistance.h"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <iostream>

namespace ldae::runtime {

std::string formatValue(double v) {
  // fmt never uses the locale unless asked: always a '.' decimal point.
  return fmt::format("{:.17g}", v);
}

static std::string csvField(const std::string &s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void writeCsv(const SimResult &result, std::ostream &out) {
  std::string line;
  for (size_t c = 0; c < result.columns.size(); ++c)
    line += (c ? "," : "") + csvField(result.columns[c]);
  out << line << '\n';
  for (const auto &row : result.rows) {
    line.clear();
    for (size_t c = 0; c < row.size(); ++c) {
      if (c)
        line += ',';
      line += formatValue(row[c]);
    }
    out << line << '\n';
  }
  out.flush();
}

Expected<bool> writeCsv(const SimResult &result, const std::string &path) {
  if (path == "-") {
    writeCsv(result, std::cout);
    return true;
  }
  std::ofstream f(path);
  if (!f)
    return Error{fmt::format("cannot write '{}'", path)};
  writeCsv(result, f);
  if (!f)
    return Error{fmt::format("cannot write '{}'", path)};
  return true;
}

std::vector<std::string> closeNames(const std::vector<std::string> &available,
                                    const std::string &name, size_t limit) {
  std::vector<std::pair<size_t, std::string>> scored;
  size_t maxDist = std::max<size_t>(1, name.size() / 4);
  for (const auto &a : available) {
    size_t d = editDistance(a, name);
    bool sub = !name.empty() && (a.find(name) != std::string::npos ||
                                 name.find(a) != std::string::npos);
    if (d <= maxDist || sub)
      scored.push_back({sub ? std::min(d, maxDist) : d, a});
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](auto &x, auto &y) { return x.first < y.first; });
  std::vector<std::string> out;
  for (size_t i = 0; i < scored.size() && i < limit; ++i)
    out.push_back(scored[i].second);
  return out;
}

Error unknownNameError(const std::string &kind, const std::string &name,
                       const std::vector<std::string> &available) {
  std::vector<std::string> close = closeNames(available, name);
  std::string hint;
  for (size_t i = 0; i < close.size(); ++i)
    hint += (i ? ", '" : "'") + close[i] + "'";
  if (close.empty())
    return Error{fmt::format("unknown {} '{}'", kind, name)};
  return Error{
      fmt::format("unknown {} '{}'; did you mean {}?", kind, name, hint)};
}

Expected<std::vector<int>>
selectColumns(const std::vector<std::string> &available,
              const std::vector<std::string> &wanted) {
  std::vector<int> idx;
  for (const auto &w : wanted) {
    auto it = std::find(available.begin(), available.end(), w);
    if (it != available.end()) {
      idx.push_back(int(it - available.begin()));
      continue;
    }
    return unknownNameError("output", w, available);
  }
  return idx;
}

} // namespace ldae::runtime
