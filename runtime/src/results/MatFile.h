// A MATLAB version 4 file: the container of the result files OpenModelica
// and Dymola write (docs/results.md). Only what those files hold: double
// matrices and text matrices, little-endian, and one double matrix whose
// column count is known only at the end (the trajectories of a run,
// written as it goes).
#pragma once

#include "support/Expected.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ldae::runtime {

/// One open v4 file. Matrices are appended in the order written; the file
/// is complete after close(). Every write is checked: an Error names the
/// file and the reason (errno), and close() after a failed write removes
/// the partial file.
class MatFile {
public:
  /// Creates (truncates) `path`; an Error names the path and the reason.
  static Expected<MatFile> create(const std::string &path);

  MatFile(MatFile &&) noexcept;
  MatFile &operator=(MatFile &&) noexcept;
  /// Closes without the checks of close() (after an error).
  ~MatFile();

  /// A rows x cols double matrix named `name` from `data`, stored column
  /// by column (data[r + c * rows]), as the file keeps it.
  Expected<bool> writeMatrix(const std::string &name, size_t rows, size_t cols,
                             const double *data);

  /// Overwrites element (r, c) of the last matrix writeMatrix wrote (a
  /// value known only when the run ends: its stop time).
  Expected<bool> overwriteLast(size_t r, size_t c, double value);

  /// A char matrix of `strings`, shorter ones padded with blanks. By rows:
  /// string i is row i (MATLAB's char(...)); by columns: string i is
  /// column i (the transposed layout of OpenModelica's `name` and
  /// `description`).
  Expected<bool> writeStrings(const std::string &name,
                              const std::vector<std::string> &strings,
                              bool byColumns);

  /// Starts the double matrix `name` of `rows` rows whose columns follow
  /// with appendColumn; close() writes their count into its header. It
  /// must be the file's last matrix.
  Expected<bool> beginColumns(const std::string &name, size_t rows);
  /// One column (`rows` values) of the matrix beginColumns started.
  Expected<bool> appendColumn(const double *column);

  /// Completes the file (the open matrix's column count), flushes and
  /// closes it; an Error when the data did not reach the disk (the
  /// partial file is then removed).
  Expected<bool> close();

private:
  struct Handle;
  explicit MatFile(std::unique_ptr<Handle> handle);
  std::unique_ptr<Handle> handle_;
};

} // namespace ldae::runtime
