// A MATLAB version 4 file written through libmatio: the container of the
// result files OpenModelica and Dymola write (docs/results.md). Only what
// those files hold: double matrices and char matrices.
#pragma once

#include "support/Expected.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace ldae::runtime {

/// One open v4 file. Matrices are appended in the order written; the file
/// is complete after close() (or the destructor, which ignores errors).
class MatFile {
public:
  /// Creates (truncates) `path`; an Error names the path.
  static Expected<MatFile> create(const std::string &path);

  MatFile(MatFile &&) noexcept;
  MatFile &operator=(MatFile &&) noexcept;
  ~MatFile();

  /// A rows x cols double matrix named `name` from `data`, stored column
  /// by column (data[r + c * rows]), as the file keeps it.
  Expected<bool> writeMatrix(const std::string &name, size_t rows, size_t cols,
                             const double *data);

  /// A char matrix of `strings`, shorter ones padded with blanks. By rows:
  /// string i is row i (MATLAB's char(...)); by columns: string i is
  /// column i (the transposed layout of OpenModelica's `name` and
  /// `description`).
  Expected<bool> writeStrings(const std::string &name,
                              const std::vector<std::string> &strings,
                              bool byColumns);

  /// Flushes and closes; an Error when the data did not reach the disk.
  Expected<bool> close();

private:
  struct Handle;
  explicit MatFile(std::unique_ptr<Handle> handle);
  std::unique_ptr<Handle> handle_;
};

} // namespace ldae::runtime
