// The command-line sweep (see Sweep.h, docs/results.md "Sweeps"). Members
// run on a pool of threads that take the next member from one counter, so
// a slow member holds up one thread only. Each member writes its log to a
// buffer of its own, printed whole after its progress line: lines of
// members running at once never interleave.
#include "ldae/Sweep.h"
#include "results/MatFile.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace ldae::runtime {

namespace {

/// `text` without surrounding blanks.
std::string trim(const std::string &text) {
  size_t b = text.find_first_not_of(" \t");
  if (b == std::string::npos)
    return "";
  return text.substr(b, text.find_last_not_of(" \t") - b + 1);
}

/// The finite number spelled by all of `text`, or an Error quoting it.
/// from_chars reads `.` as the decimal point whatever the locale.
Expected<double> parseNumber(const std::string &text) {
  std::string t = trim(text);
  const char *first = t.data(), *last = t.data() + t.size();
  if (first != last && *first == '+')
    ++first;
  double v = 0;
  auto [end, ec] = std::from_chars(first, last, v);
  // An underflow (1e-400) is 0, as the command line's --param reads it;
  // an overflow is no finite number.
  if (ec == std::errc::result_out_of_range && end == last) {
    std::string exponent(std::find_if(first, last,
                                      [](char c) { return c == 'e' || c == 'E'; }),
                         last);
    if (exponent.size() > 1 && exponent[1] == '-') {
      v = *first == '-' ? -0.0 : 0.0;
      ec = std::errc();
    }
  }
  if (t.empty() || ec != std::errc() || end != last || !std::isfinite(v))
    return Error{fmt::format("'{}' is not a finite number", t)};
  return v;
}

/// Splits `text` at every `sep`.
std::vector<std::string> split(const std::string &text, char sep) {
  std::vector<std::string> parts;
  size_t at = 0;
  for (size_t next; (next = text.find(sep, at)) != std::string::npos;
       at = next + 1)
    parts.push_back(text.substr(at, next - at));
  parts.push_back(text.substr(at));
  return parts;
}

/// "R=2, C=0.001": a member's parameters for progress lines.
std::string describe(const std::map<std::string, double> &params) {
  std::string s;
  for (const auto &[name, value] : params)
    s += (s.empty() ? "" : ", ") + name + "=" + formatValue(value);
  return s;
}

/// The first line of `text`.
std::string firstLine(const std::string &text) {
  return text.substr(0, text.find('\n'));
}

/// Runs one member, turning an escaping exception (out of memory) into an
/// Error of the member: the others go on.
Expected<SimResult>
runMember(const std::function<Expected<SimResult>(const SimOptions &)> &simulate,
          const SimOptions &opts) {
  try {
    return simulate(opts);
  } catch (const std::exception &e) {
    return Error{fmt::format("internal error: {}", e.what())};
  }
}

} // namespace

Expected<SweepAxis> parseSweepAxis(const std::string &spec) {
  size_t eq = spec.find('=');
  if (eq == std::string::npos)
    return Error{"expected name=first:last:count or name=v1,v2,..."};
  SweepAxis axis;
  axis.name = trim(spec.substr(0, eq));
  if (axis.name.empty())
    return Error{"no parameter name before '='"};
  std::string values = spec.substr(eq + 1);
  if (values.find(':') != std::string::npos) {
    std::vector<std::string> parts = split(values, ':');
    if (parts.size() != 3)
      return Error{"a range is first:last:count"};
    Expected<double> first = parseNumber(parts[0]);
    Expected<double> last = parseNumber(parts[1]);
    if (!first)
      return Error{first.error()};
    if (!last)
      return Error{last.error()};
    std::string countText = trim(parts[2]);
    long count = 0;
    auto [end, ec] = std::from_chars(
        countText.data(), countText.data() + countText.size(), count);
    if (ec != std::errc() || end != countText.data() + countText.size() ||
        count < 2 || count > long(kMaxSweepMembers))
      return Error{fmt::format("the count '{}' must be an integer from 2 to "
                               "{}",
                               countText, kMaxSweepMembers)};
    for (long k = 0; k < count; ++k)
      axis.values.push_back(k + 1 == count
                                ? *last
                                : *first + (*last - *first) * double(k) /
                                               double(count - 1));
    return axis;
  }
  for (const std::string &part : split(values, ',')) {
    Expected<double> v = parseNumber(part);
    if (!v)
      return Error{v.error()};
    axis.values.push_back(*v);
  }
  return axis;
}

Expected<bool> checkSweepAxes(const std::vector<SweepAxis> &axes) {
  double members = axes.empty() ? 0 : 1;
  for (size_t i = 0; i < axes.size(); ++i) {
    for (size_t j = 0; j < i; ++j)
      if (axes[i].name == axes[j].name)
        return Error{fmt::format("'{}' is swept twice (list every value in "
                                 "one --sweep)",
                                 axes[i].name)};
    members *= double(axes[i].values.size());
  }
  if (members > double(kMaxSweepMembers))
    return Error{fmt::format("the grid has {:g} members, more than the limit "
                             "of {} (every member's result is kept until the "
                             "file is written)",
                             members, kMaxSweepMembers)};
  return true;
}

std::vector<std::map<std::string, double>>
sweepMembers(const std::vector<SweepAxis> &axes) {
  std::vector<std::map<std::string, double>> members;
  if (axes.empty())
    return members;
  // An odometer over the axes, the last digit turning fastest.
  std::vector<size_t> at(axes.size(), 0);
  for (const SweepAxis &a : axes)
    if (a.values.empty())
      return members;
  while (true) {
    std::map<std::string, double> m;
    for (size_t i = 0; i < axes.size(); ++i)
      m[axes[i].name] = axes[i].values[at[i]];
    members.push_back(std::move(m));
    size_t i = axes.size();
    while (i > 0 && ++at[i - 1] == axes[i - 1].values.size())
      at[--i] = 0;
    if (i == 0)
      return members;
  }
}

namespace {

/// The progress lines and members' logs of one sweep, written whole under
/// one lock as members finish. A log line already written for an earlier
/// member (the same initialization report a thousand times) is not
/// repeated.
class SweepReport {
public:
  SweepReport(size_t members, std::ostream *progress, std::ostream *log)
      : members_(members), progress_(progress), log_(log) {}

  void finished(size_t k, const SweepMember &m, double seconds,
                const std::string &log) {
    const Expected<SimResult> &r = m.result;
    std::string failure = !r ? r.error() : r->status != 0 ? r->failure : "";
    std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    if (progress_)
      *progress_ << fmt::format(
          "sweep: {} of {} done; member {} ({}) {}\n", done_, members_, k + 1,
          describe(m.params),
          failure.empty() ? fmt::format("ok ({:.3g} s)", seconds)
                          : "failed: " + firstLine(failure));
    if (!log_)
      return;
    // The rest of a failure's message (its hint) belongs to the log.
    size_t rest = failure.find('\n');
    std::istringstream lines(
        log + (rest == std::string::npos ? "" : failure.substr(rest + 1)));
    for (std::string line; std::getline(lines, line);)
      if (seen_.insert(line).second)
        *log_ << fmt::format("member {}: {}\n", k + 1, line);
  }

private:
  std::mutex mutex_;
  size_t done_ = 0, members_;
  std::ostream *progress_, *log_;
  std::set<std::string> seen_;
};

} // namespace

std::vector<SweepMember>
runSweep(const std::function<Expected<SimResult>(const SimOptions &)> &simulate,
         const SimOptions &base,
         const std::vector<std::map<std::string, double>> &members, int jobs,
         std::ostream *progress) {
  std::vector<SweepMember> out(members.size());
  size_t threads = jobs > 0 ? size_t(jobs)
                            : std::max(1u, std::thread::hardware_concurrency());
  threads = std::min(threads, members.size());
  std::atomic<size_t> next{0};
  SweepReport report(members.size(), progress, base.log);
  auto work = [&] {
    for (size_t k; (k = next.fetch_add(1)) < members.size();) {
      auto t0 = std::chrono::steady_clock::now();
      SimOptions opts = base;
      for (const auto &[name, value] : members[k])
        opts.params[name] = value;
      std::ostringstream log;
      if (base.log)
        opts.log = &log;
      out[k].params = members[k];
      out[k].result = runMember(simulate, opts);
      report.finished(k, out[k],
                      std::chrono::duration<double>(
                          std::chrono::steady_clock::now() - t0)
                          .count(),
                      log.str());
    }
  };
  std::vector<std::thread> pool;
  for (size_t i = 1; i < threads; ++i)
    pool.emplace_back(work);
  work(); // this thread is one of the pool
  for (std::thread &t : pool)
    t.join();
  return out;
}

namespace {

/// A member's status in the file: 0 ok, 3 numerical failure, 2 refused
/// options.
int statusOf(const SweepMember &m) {
  return !m.result ? 2 : m.result->status == 0 ? 0 : 3;
}

/// Why a member failed, on one line ("" when it did not).
std::string failureOf(const SweepMember &m) {
  std::string text = !m.result ? m.result.error() : m.result->failure;
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

/// The column names every member with a result shares; an Error when two
/// members' differ (they come from one compiled model, so they never
/// should).
Expected<std::vector<std::string>>
sharedColumns(const std::vector<SweepMember> &members) {
  const std::vector<std::string> *columns = nullptr;
  for (const SweepMember &m : members) {
    if (!m.result)
      continue;
    if (columns && m.result->columns != *columns)
      return Error{"the sweep's members report different columns"};
    columns = &m.result->columns;
  }
  return columns ? *columns : std::vector<std::string>{"time"};
}

/// The swept parameter names, sorted (the members' maps keep them so).
std::vector<std::string> sweptNames(const std::vector<SweepMember> &members) {
  std::vector<std::string> names;
  if (!members.empty())
    for (const auto &entry : members.front().params)
      names.push_back(entry.first);
  return names;
}

/// The long table. A parameter column of the result that is also swept
/// is written once, among the swept ones: a reader keys columns by name.
Expected<bool> writeSweepCsv(const std::vector<SweepMember> &members,
                             const std::vector<std::string> &columns,
                             std::ostream &out) {
  std::vector<std::string> swept = sweptNames(members);
  std::string header = "member";
  for (const std::string &name : swept)
    header += "," + name;
  std::vector<size_t> kept;
  for (size_t c = 0; c < columns.size(); ++c)
    if (c == 0 || std::find(swept.begin(), swept.end(), columns[c]) ==
                      swept.end()) {
      kept.push_back(c);
      header += "," + columns[c];
    }
  out << header << '\n';
  for (size_t k = 0; k < members.size(); ++k) {
    if (!members[k].result)
      continue;
    std::string prefix = std::to_string(k + 1);
    for (const auto &entry : members[k].params)
      prefix += "," + formatValue(entry.second);
    for (const std::vector<double> &row : members[k].result->rows) {
      std::string line = prefix;
      for (size_t c : kept)
        line += "," + formatValue(row[c]);
      out << line << '\n';
    }
  }
  out.flush();
  if (!out)
    return Error{"cannot write the sweep's CSV"};
  return true;
}

Expected<bool> writeSweepMat(const std::vector<SweepMember> &members,
                             const std::vector<std::string> &columns,
                             const std::string &path) {
  if (path == "-")
    return Error{"a .mat sweep file needs a file name (-o sweep.mat)"};
  Expected<MatFile> file = MatFile::create(path);
  if (!file)
    return Error{file.error()};
  std::vector<std::string> names = sweptNames(members);
  std::vector<double> values(members.size() * names.size()),
      status(members.size());
  std::vector<std::string> failures;
  for (size_t k = 0; k < members.size(); ++k) {
    size_t a = 0;
    for (const auto &entry : members[k].params)
      values[k + a++ * members.size()] = entry.second;
    status[k] = statusOf(members[k]);
    failures.push_back(failureOf(members[k]));
  }
  std::vector<Expected<bool>> written;
  written.push_back(file->writeStrings("sweep_names", names, false));
  written.push_back(file->writeMatrix("sweep_values", members.size(),
                                      names.size(), values.data()));
  written.push_back(
      file->writeMatrix("status", members.size(), 1, status.data()));
  written.push_back(file->writeStrings("failure", failures, false));
  written.push_back(file->writeStrings("name", columns, false));
  for (size_t k = 0; k < members.size(); ++k) {
    std::vector<double> data;
    size_t rows = 0;
    if (members[k].result) {
      const std::vector<std::vector<double>> &table = members[k].result->rows;
      rows = table.size();
      data.resize(rows * columns.size());
      for (size_t r = 0; r < rows; ++r)
        for (size_t c = 0; c < columns.size(); ++c)
          data[r + c * rows] = table[r][c];
    }
    written.push_back(file->writeMatrix(fmt::format("member_{}", k + 1), rows,
                                        columns.size(), data.data()));
  }
  // The file's outcome says also what became of a partial file.
  if (auto closed = file->close(); !closed)
    return closed;
  for (const Expected<bool> &w : written)
    if (!w)
      return Error{w.error()};
  return true;
}

} // namespace

Expected<bool> writeSweep(const std::vector<SweepMember> &members,
                          const std::string &path, ResultFormat format) {
  Expected<std::vector<std::string>> columns = sharedColumns(members);
  if (!columns)
    return Error{columns.error()};
  if (format == ResultFormat::Mat)
    return writeSweepMat(members, *columns, path);
  if (path == "-")
    return writeSweepCsv(members, *columns, std::cout);
  std::ofstream f(path);
  if (!f)
    return Error{fmt::format("cannot write '{}'", path)};
  return writeSweepCsv(members, *columns, f);
}

} // namespace ldae::runtime
