// Writing simulation results (docs/results.md): CSV with a header of
// names, `.` decimal point and the shortest digits that round-trip, or the
// .mat layout of OpenModelica and Dymola (MatResult.h).
#pragma once

#include "ldae/Simulation.h"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace ldae::runtime {

/// The result file formats (docs/results.md).
enum class ResultFormat { Csv, Mat };

/// The format of `path` by its extension (.mat: Mat, else Csv), or the
/// one `forced` names ("csv", "mat"); an Error for another name.
Expected<ResultFormat> resultFormat(const std::string &path,
                                    const std::string &forced = "");

/// A result file written as the run goes (SimOptions::rowSink), so that a
/// long run holds none of its rows, completed by finish().
class ResultFile : public RowSink {
public:
  /// The file `path` ("-" is standard output, CSV only) in `format`;
  /// nothing is opened before begin().
  static Expected<std::unique_ptr<ResultFile>> open(const std::string &path,
                                                    ResultFormat format);
  /// After the run: the header when no row came, the .mat's sizes, the
  /// flush. An Error names the file and the reason (errno); a partial file
  /// is removed, never passed off as whole.
  virtual Expected<bool> finish(const SimResult &result) = 0;
};

/// Writes `result` (its rows) to `path` ("-" is stdout, CSV only) in
/// `format`, through ResultFile.
Expected<bool> writeResult(const SimResult &result, const std::string &path,
                           ResultFormat format);

/// Writes `result` as CSV to `out`.
void writeCsv(const SimResult &result, std::ostream &out);

/// Formats one value as the CSV does: the shortest text that reads back to
/// the same double, `.` point.
std::string formatValue(double v);

/// Indices into `available` of the `wanted` names, in the order asked.
/// An unknown name is an Error that lists the closest available names.
Expected<std::vector<int>>
selectColumns(const std::vector<std::string> &available,
              const std::vector<std::string> &wanted);

/// "unknown <kind> 'name'; did you mean 'a', 'b'?" (the close names from
/// `available`, if any).
Error unknownNameError(const std::string &kind, const std::string &name,
                       const std::vector<std::string> &available);

/// Names in `available` close to `name` (edit distance or substring), best
/// first, at most `limit`.
std::vector<std::string> closeNames(const std::vector<std::string> &available,
                                    const std::string &name, size_t limit = 5);

} // namespace ldae::runtime
