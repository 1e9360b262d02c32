// MATLAB v4 files through libmatio (see MatFile.h). libmatio is loaded
// when the first file is written, not linked: it brings HDF5, curl, TLS
// and Kerberos with it (35 shared libraries), which every ldaec process
// would map at start-up though few write a .mat file (docs/results.md).
#include "MatFile.h"

#include <algorithm>
#include <cstdio>
#include <dlfcn.h>
#include <sys/stat.h>
#include <fmt/format.h>
#include <matio.h>

namespace ldae::runtime {

namespace {

/// The libmatio functions MatFile uses, resolved once.
struct Matio {
  decltype(&Mat_CreateVer) createVer = nullptr;
  decltype(&Mat_Close) close = nullptr;
  decltype(&Mat_VarCreate) varCreate = nullptr;
  decltype(&Mat_VarWrite) varWrite = nullptr;
  decltype(&Mat_VarFree) varFree = nullptr;
  std::string error; // why it could not be loaded ("" when loaded)
};

template <typename F> bool resolve(void *lib, const char *name, F &fn) {
  fn = reinterpret_cast<F>(dlsym(lib, name));
  return fn != nullptr;
}

const Matio &matio() {
  static const Matio m = [] {
    Matio m;
    void *lib = dlopen(LDAE_MATIO_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      const char *why = dlerror();
      m.error = fmt::format("cannot load libmatio ({}): {}", LDAE_MATIO_LIBRARY,
                            why ? why : "unknown error");
      return m;
    }
    if (!resolve(lib, "Mat_CreateVer", m.createVer) ||
        !resolve(lib, "Mat_Close", m.close) ||
        !resolve(lib, "Mat_VarCreate", m.varCreate) ||
        !resolve(lib, "Mat_VarWrite", m.varWrite) ||
        !resolve(lib, "Mat_VarFree", m.varFree))
      m.error = fmt::format("{} lacks the functions ldaec writes with",
                            LDAE_MATIO_LIBRARY);
    return m;
  }();
  return m;
}

} // namespace

struct MatFile::Handle {
  mat_t *mat = nullptr;
  std::string path;
  /// What the variables written take in a MATLAB v4 file: matio does not
  /// say when a write fails (a full disk), the file's size does.
  uint64_t bytes = 0;
  ~Handle() {
    if (mat)
      matio().close(mat);
  }
};

MatFile::MatFile(std::unique_ptr<Handle> handle) : handle_(std::move(handle)) {}
MatFile::MatFile(MatFile &&) noexcept = default;
MatFile &MatFile::operator=(MatFile &&) noexcept = default;
MatFile::~MatFile() = default;

Expected<MatFile> MatFile::create(const std::string &path) {
  if (!matio().error.empty())
    return Error{fmt::format("cannot write '{}': {}", path, matio().error)};
  auto h = std::make_unique<Handle>();
  h->path = path;
  h->mat = matio().createVer(path.c_str(), nullptr, MAT_FT_MAT4);
  if (!h->mat)
    return Error{fmt::format("cannot write '{}'", path)};
  return MatFile(std::move(h));
}

namespace {

/// A v4 variable in the file: a 20-byte header, the name with its NUL,
/// the elements.
uint64_t v4Bytes(const std::string &name, size_t rows, size_t cols,
                 size_t element) {
  return 20 + name.size() + 1 + uint64_t(rows) * cols * element;
}

/// Writes one variable; matio copies `data`, so it may be a temporary.
bool writeVar(mat_t *mat, const std::string &name, matio_classes cls,
              matio_types type, size_t rows, size_t cols, const void *data) {
  size_t dims[2] = {rows, cols};
  matvar_t *var = matio().varCreate(name.c_str(), cls, type, 2, dims,
                                    const_cast<void *>(data), 0);
  if (!var)
    return false;
  int rc = matio().varWrite(mat, var, MAT_COMPRESSION_NONE);
  matio().varFree(var);
  return rc == 0;
}

} // namespace

Expected<bool> MatFile::writeMatrix(const std::string &name, size_t rows,
                                    size_t cols, const double *data) {
  static const double kNone = 0;
  if (!handle_ || !handle_->mat)
    return Error{fmt::format("'{}' is closed", name)};
  if (!writeVar(handle_->mat, name, MAT_C_DOUBLE, MAT_T_DOUBLE, rows, cols,
                rows != 0 && cols != 0 ? data : &kNone))
    return Error{fmt::format("cannot write '{}' to '{}'", name, handle_->path)};
  handle_->bytes += v4Bytes(name, rows, cols, sizeof(double));
  return true;
}

Expected<bool> MatFile::writeStrings(const std::string &name,
                                     const std::vector<std::string> &strings,
                                     bool byColumns) {
  if (!handle_ || !handle_->mat)
    return Error{fmt::format("'{}' is closed", name)};
  size_t width = 1; // a char matrix of no columns reads back badly
  for (const std::string &s : strings)
    width = std::max(width, s.size());
  size_t n = strings.size();
  std::vector<unsigned char> chars(std::max<size_t>(n, 1) * width, ' ');
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < strings[i].size(); ++j)
      // Column-major: by columns string i fills column i of width rows.
      chars[byColumns ? j + i * width : i + j * n] =
          static_cast<unsigned char>(strings[i][j]);
  size_t rows = byColumns ? width : n, cols = byColumns ? n : width;
  if (!writeVar(handle_->mat, name, MAT_C_CHAR, MAT_T_UINT8, rows, cols,
                chars.data()))
    return Error{fmt::format("cannot write '{}' to '{}'", name, handle_->path)};
  handle_->bytes += v4Bytes(name, rows, cols, 1);
  return true;
}

Expected<bool> MatFile::close() {
  if (!handle_ || !handle_->mat)
    return true;
  int rc = matio().close(handle_->mat);
  handle_->mat = nullptr;
  const std::string &path = handle_->path;
  if (rc != 0)
    return Error{fmt::format("cannot write '{}'", path)};
  struct stat st;
  if (path == "/dev/null")
    return true;
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
    return Error{fmt::format("cannot write '{}': not a regular file", path)};
  if (uint64_t(st.st_size) != handle_->bytes) {
    std::remove(path.c_str());
    return Error{fmt::format("cannot write '{}': {} of its {} bytes reached "
                             "the file (is the disk full?); the partial file "
                             "was removed",
                             path, uint64_t(st.st_size), handle_->bytes)};
  }
  return true;
}

} // namespace ldae::runtime
