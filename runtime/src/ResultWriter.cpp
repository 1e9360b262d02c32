// Result files (CSV here, .mat in MatResult.cpp) and column selection by
// name (see ResultWriter.h).
#include "ResultWriter.h"
#include "MatResult.h"
#include "support/EditDistance.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <string_view>
#include <unordered_map>

namespace ldae::runtime {

namespace {

/// Longest text std::to_chars writes for a double in its shortest form
/// ("-2.2250738585072014e-308" is 24 characters).
constexpr size_t kMaxNumberChars = 32;

/// Writes the shortest text that reads back to the same double: never the
/// locale's decimal point, "inf", "-inf" and "nan" as strtod reads them.
char *putValue(char *at, double v) {
  return std::to_chars(at, at + kMaxNumberChars, v).ptr;
}

} // namespace

std::string formatValue(double v) {
  char buf[kMaxNumberChars];
  return std::string(buf, putValue(buf, v));
}

static std::string csvField(const std::string &s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// Numbers go straight into one buffer written in large blocks: formatting
// a string per value ran at 45 MB/s, slower than integrating a large model.
void writeCsv(const SimResult &result, std::ostream &out) {
  std::string header;
  for (size_t c = 0; c < result.columns.size(); ++c)
    header += (c ? "," : "") + csvField(result.columns[c]);
  out << header << '\n';
  constexpr size_t kBlock = 1 << 20;
  // Not zero-filled: a small result then touches only the pages it writes
  // (zeroing the whole block cost a 13-row run 1 M instructions and 256
  // page faults).
  auto buf = std::make_unique_for_overwrite<char[]>(kBlock + kMaxNumberChars + 2);
  char *at = buf.get();
  for (const auto &row : result.rows) {
    for (size_t c = 0; c < row.size(); ++c) {
      if (c)
        *at++ = ',';
      at = putValue(at, row[c]);
      if (at - buf.get() >= static_cast<ptrdiff_t>(kBlock)) {
        out.write(buf.get(), at - buf.get());
        at = buf.get();
      }
    }
    *at++ = '\n';
  }
  out.write(buf.get(), at - buf.get());
  out.flush();
}

Expected<bool> writeCsv(const SimResult &result, const std::string &path) {
  // Every write is checked, with the reason (a full disk says so); a file
  // that could not be written whole is removed, never passed off as whole.
  if (path == "-") {
    errno = 0;
    writeCsv(result, std::cout);
    if (!std::cout)
      return Error{fmt::format("cannot write the results to standard output: "
                               "{}",
                               errno ? std::strerror(errno) : "write error")};
    return true;
  }
  errno = 0;
  std::ofstream f(path);
  if (!f)
    return Error{fmt::format("cannot write '{}': {}", path,
                             errno ? std::strerror(errno) : "open failed")};
  writeCsv(result, f);
  f.close();
  if (!f) {
    int why = errno;
    struct stat st;
    bool removed = ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
                   std::remove(path.c_str()) == 0;
    return Error{fmt::format("cannot write '{}': {}{}", path,
                             why ? std::strerror(why) : "write error",
                             removed ? " (the partial file was removed)" : "")};
  }
  return true;
}

Expected<ResultFormat> resultFormat(const std::string &path,
                                    const std::string &forced) {
  if (forced == "csv")
    return ResultFormat::Csv;
  if (forced == "mat")
    return ResultFormat::Mat;
  if (!forced.empty())
    return Error{fmt::format("unknown result format '{}' (csv or mat)",
                             forced)};
  const std::string ext = ".mat";
  bool mat = path.size() > ext.size() &&
             path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
  return mat ? ResultFormat::Mat : ResultFormat::Csv;
}

Expected<bool> writeResult(const SimResult &result, const std::string &path,
                           ResultFormat format) {
  if (format == ResultFormat::Csv)
    return writeCsv(result, path);
  if (path == "-")
    return Error{"a .mat result cannot go to standard output; name a file "
                 "with -o"};
  return writeMat(result, path);
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
  // Not a search per name: the driver asks for every output of the model
  // by name, quadratic at 10^5 outputs. It asks in the model's order
  // (leaving some out), so the few names after the last match are tried
  // first; the others are found by binary search when the names are sorted
  // (compiled models sort them) or else by a hash index, built once. A
  // model's names are unique, so the match is the one a linear search
  // would find.
  enum { Unknown, Sorted, Hashed } lookup = Unknown;
  std::unordered_map<std::string_view, size_t> index;
  auto find = [&](const std::string &w) -> size_t {
    if (lookup == Unknown) {
      lookup = std::is_sorted(available.begin(), available.end()) ? Sorted
                                                                  : Hashed;
      if (lookup == Hashed) {
        index.reserve(available.size());
        for (size_t i = 0; i < available.size(); ++i)
          index.emplace(available[i], i);
      }
    }
    if (lookup == Sorted) {
      auto it = std::lower_bound(available.begin(), available.end(), w);
      return it != available.end() && *it == w ? size_t(it - available.begin())
                                               : available.size();
    }
    auto it = index.find(w);
    return it == index.end() ? available.size() : it->second;
  };
  size_t next = 0;
  std::vector<int> idx;
  idx.reserve(wanted.size());
  for (const auto &w : wanted) {
    size_t end = std::min(available.size(), next + 16), at = next;
    while (at < end && available[at] != w)
      ++at;
    if (at == end)
      at = find(w);
    if (at == available.size())
      return unknownNameError("output", w, available);
    idx.push_back(int(at));
    next = at + 1;
  }
  return idx;
}

} // namespace ldae::runtime
