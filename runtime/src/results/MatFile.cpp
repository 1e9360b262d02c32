// MATLAB v4 files (see MatFile.h), written from MathWorks' "MAT-File
// Format" (Level 4): each matrix is a header of five 32-bit integers (type
// MOPT, rows, columns, imaginary flag, name length with its NUL), the name,
// then the elements column by column. Written here rather than through
// libmatio, which writes a matrix only whole: the trajectories of a long
// run go to the file as they come, and their count is patched into the
// header at the end (docs/results.md).
#include "results/MatFile.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <fmt/format.h>

namespace ldae::runtime {

static_assert(std::endian::native == std::endian::little,
              "the v4 files are written little-endian (MOPT M = 0)");

namespace {

/// MOPT of a full double matrix and of a text matrix of bytes.
constexpr int32_t kDouble = 0, kText = 51;

} // namespace

struct MatFile::Handle {
  std::FILE *file = nullptr;
  std::string path;
  std::string failure; // the first failed write ("" while all went well)
  long lastData = -1;  // offset of the last writeMatrix's elements
  size_t lastRows = 0, lastCols = 0;
  long openHeader = -1; // offset of beginColumns' header
  size_t openRows = 0, openCols = 0;

  ~Handle() {
    if (file)
      std::fclose(file);
  }
  bool put(const void *data, size_t bytes) {
    if (!failure.empty())
      return false;
    errno = 0;
    if (bytes != 0 && std::fwrite(data, 1, bytes, file) != bytes) {
      failure = errno ? std::strerror(errno) : "write error";
      return false;
    }
    return true;
  }
  bool header(int32_t type, size_t rows, size_t cols, const std::string &name) {
    int32_t h[5] = {type, int32_t(rows), int32_t(cols), 0,
                    int32_t(name.size() + 1)};
    return put(h, sizeof h) && put(name.c_str(), name.size() + 1);
  }
  Error error(const std::string &what) const {
    return Error{fmt::format("cannot write {}'{}': {}", what, path, failure)};
  }
};

MatFile::MatFile(std::unique_ptr<Handle> handle) : handle_(std::move(handle)) {}
MatFile::MatFile(MatFile &&) noexcept = default;
MatFile &MatFile::operator=(MatFile &&) noexcept = default;
MatFile::~MatFile() = default;

Expected<MatFile> MatFile::create(const std::string &path) {
  auto h = std::make_unique<Handle>();
  h->path = path;
  errno = 0;
  h->file = std::fopen(path.c_str(), "wb");
  if (!h->file)
    return Error{fmt::format("cannot write '{}': {}", path,
                             errno ? std::strerror(errno) : "open failed")};
  return MatFile(std::move(h));
}

namespace {

/// A v4 matrix holds at most 2^31 - 1 rows and columns.
bool fits(size_t rows, size_t cols) {
  return rows <= size_t(INT32_MAX) && cols <= size_t(INT32_MAX);
}

} // namespace

Expected<bool> MatFile::writeMatrix(const std::string &name, size_t rows,
                                    size_t cols, const double *data) {
  Handle &h = *handle_;
  if (!fits(rows, cols))
    return Error{fmt::format("'{}' is too large for a v4 file", name)};
  if (!h.header(kDouble, rows, cols, name))
    return h.error("");
  h.lastData = std::ftell(h.file);
  h.lastRows = rows;
  h.lastCols = cols;
  if (!h.put(data, rows * cols * sizeof(double)))
    return h.error("");
  return true;
}

Expected<bool> MatFile::overwriteLast(size_t r, size_t c, double value) {
  Handle &h = *handle_;
  if (h.lastData < 0 || r >= h.lastRows || c >= h.lastCols)
    return Error{fmt::format("no element ({}, {}) to overwrite in '{}'", r, c,
                             h.path)};
  long end = std::ftell(h.file);
  long at = h.lastData + long((r + c * h.lastRows) * sizeof(double));
  if (std::fseek(h.file, at, SEEK_SET) != 0 || !h.put(&value, sizeof value) ||
      std::fseek(h.file, end, SEEK_SET) != 0) {
    if (h.failure.empty())
      h.failure = std::strerror(errno);
    return h.error("");
  }
  return true;
}

Expected<bool> MatFile::writeStrings(const std::string &name,
                                     const std::vector<std::string> &strings,
                                     bool byColumns) {
  Handle &h = *handle_;
  size_t width = 1; // a char matrix of no columns reads back badly
  for (const std::string &s : strings)
    width = std::max(width, s.size());
  size_t n = std::max<size_t>(strings.size(), 1);
  std::vector<unsigned char> chars(n * width, ' ');
  for (size_t i = 0; i < strings.size(); ++i)
    for (size_t j = 0; j < strings[i].size(); ++j)
      // Column-major: by columns string i fills column i of width rows.
      chars[byColumns ? j + i * width : i + j * n] =
          static_cast<unsigned char>(strings[i][j]);
  size_t rows = byColumns ? width : n, cols = byColumns ? n : width;
  if (!fits(rows, cols))
    return Error{fmt::format("'{}' is too large for a v4 file", name)};
  if (!h.header(kText, rows, cols, name) || !h.put(chars.data(), chars.size()))
    return h.error("");
  return true;
}

Expected<bool> MatFile::beginColumns(const std::string &name, size_t rows) {
  Handle &h = *handle_;
  if (!fits(rows, 0))
    return Error{fmt::format("'{}' is too large for a v4 file", name)};
  h.openHeader = std::ftell(h.file);
  h.openRows = rows;
  h.openCols = 0;
  if (!h.header(kDouble, rows, 0, name))
    return h.error("");
  return true;
}

Expected<bool> MatFile::appendColumn(const double *column) {
  Handle &h = *handle_;
  if (h.openCols == size_t(INT32_MAX))
    return Error{fmt::format("'{}' has more columns than a v4 file holds",
                             h.path)};
  if (!h.put(column, h.openRows * sizeof(double)))
    return h.error("");
  ++h.openCols;
  return true;
}

Expected<bool> MatFile::close() {
  Handle &h = *handle_;
  if (!h.file)
    return true;
  if (h.openHeader >= 0 && h.failure.empty()) {
    // The column count, the header's third integer.
    int32_t cols = int32_t(h.openCols);
    if (std::fseek(h.file, h.openHeader + 2 * long(sizeof(int32_t)),
                   SEEK_SET) != 0)
      h.failure = std::strerror(errno);
    else
      h.put(&cols, sizeof cols);
  }
  errno = 0;
  if (std::fflush(h.file) != 0 && h.failure.empty())
    h.failure = errno ? std::strerror(errno) : "write error";
  if (std::fclose(h.file) != 0 && h.failure.empty())
    h.failure = errno ? std::strerror(errno) : "write error";
  h.file = nullptr;
  if (h.failure.empty())
    return true;
  // Never passed off as whole: a partial regular file goes.
  struct stat st;
  bool removed = ::stat(h.path.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
                 std::remove(h.path.c_str()) == 0;
  return Error{fmt::format("cannot write '{}': {}{}", h.path, h.failure,
                           removed ? " (the partial file was removed)" : "")};
}

} // namespace ldae::runtime
