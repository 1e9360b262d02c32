// Result files (CSV here, .mat in MatResult.cpp) and column selection by
// name (see ResultWriter.h).
#include "ldae/ResultWriter.h"
#include "results/MatResult.h"
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
#include <optional>
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

namespace {

/// CSV text into a stream: the header, then rows through one buffer
/// written in large blocks (formatting a string per value ran at 45 MB/s,
/// slower than integrating a large model).
class CsvStream {
public:
  static constexpr size_t kBlock = 1 << 20;

  explicit CsvStream(std::ostream &out) : out_(out) {}

  void header(const SimResult &result) {
    std::string text;
    for (size_t c = 0; c < result.columns.size(); ++c)
      text += (c ? "," : "") + csvField(result.columns[c]);
    out_ << text << '\n';
  }
  /// False when a block could not be written (the stream says why).
  bool row(const std::vector<double> &row) {
    if (!buf_) {
      // Not zero-filled: a small result then touches only the pages it
      // writes (zeroing the whole block cost a 13-row run 1 M
      // instructions and 256 page faults).
      buf_ = std::make_unique_for_overwrite<char[]>(kBlock +
                                                    kMaxNumberChars + 2);
      at_ = buf_.get();
    }
    for (size_t c = 0; c < row.size(); ++c) {
      if (c)
        *at_++ = ',';
      at_ = putValue(at_, row[c]);
      if (at_ - buf_.get() >= static_cast<ptrdiff_t>(kBlock) && !drain())
        return false;
    }
    *at_++ = '\n';
    return true;
  }
  /// Writes what is buffered and flushes the stream; false on an error.
  bool flush() {
    drain();
    out_.flush();
    return bool(out_);
  }

private:
  bool drain() {
    if (buf_)
      out_.write(buf_.get(), at_ - buf_.get());
    at_ = buf_.get();
    return bool(out_);
  }

  std::ostream &out_;
  std::unique_ptr<char[]> buf_;
  char *at_ = nullptr;
};

/// A CSV result file, or standard output ("-"), written as the run goes.
class CsvResultFile : public ResultFile {
public:
  explicit CsvResultFile(std::string path) : path_(std::move(path)) {}

  Expected<bool> begin(const SimResult &header) override {
    errno = 0;
    if (path_ != "-") {
      file_.open(path_);
      if (!file_)
        return Error{fmt::format("cannot write '{}': {}", path_,
                                 errno ? std::strerror(errno) : "open failed")};
    }
    csv_.emplace(path_ == "-" ? std::cout : file_);
    csv_->header(header);
    return true;
  }

  Expected<bool> row(const std::vector<double> &row) override {
    errno = 0;
    if (!csv_->row(row))
      return failed(errno);
    return true;
  }

  Expected<bool> finish(const SimResult &result) override {
    if (failure_)
      return *failure_;
    if (!csv_)
      if (auto ok = begin(result); !ok)
        return ok;
    errno = 0;
    bool ok = csv_->flush();
    if (path_ != "-") {
      file_.close();
      ok = ok && bool(file_);
    }
    if (!ok)
      return failed(errno);
    return true;
  }

private:
  /// Every write is checked, with the reason (a full disk says so); a file
  /// that could not be written whole is removed. The first failure is the
  /// file's outcome.
  Error failed(int why) {
    if (failure_)
      return *failure_;
    std::string reason = why ? std::strerror(why) : "write error";
    if (path_ == "-") {
      failure_ = Error{fmt::format(
          "cannot write the results to standard output: {}", reason)};
      return *failure_;
    }
    file_.close();
    struct stat st;
    bool removed = ::stat(path_.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
                   std::remove(path_.c_str()) == 0;
    failure_ = Error{fmt::format("cannot write '{}': {}{}", path_, reason,
                                 removed ? " (the partial file was removed)"
                                         : "")};
    return *failure_;
  }

  std::string path_;
  std::ofstream file_;
  std::optional<CsvStream> csv_;
  std::optional<Error> failure_;
};

} // namespace

void writeCsv(const SimResult &result, std::ostream &out) {
  CsvStream csv(out);
  csv.header(result);
  for (const auto &row : result.rows)
    csv.row(row);
  csv.flush();
}

Expected<std::unique_ptr<ResultFile>>
ResultFile::open(const std::string &path, ResultFormat format) {
  if (format == ResultFormat::Csv)
    return std::unique_ptr<ResultFile>(std::make_unique<CsvResultFile>(path));
  if (path == "-")
    return Error{"a .mat result cannot go to standard output; name a file "
                 "with -o"};
  return matResultFile(path);
}

Expected<bool> writeResult(const SimResult &result, const std::string &path,
                           ResultFormat format) {
  auto file = ResultFile::open(path, format);
  if (!file)
    return Error{file.error()};
  if (auto ok = (*file)->begin(result); !ok)
    return ok;
  for (const std::vector<double> &row : result.rows)
    if (auto ok = (*file)->row(row); !ok)
      return ok;
  return (*file)->finish(result);
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
