// The JIT's object cache; see ObjectCache.h.
#include "codegen/ObjectCache.h"

#include "codegen/JitBackend.h"

#include "llvm/Config/llvm-config.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/SHA256.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Target/TargetMachine.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <random>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace ldae::codegen {

namespace {

namespace fs = std::filesystem;

/// Bumped when the entry layout or what the key covers changes.
constexpr unsigned kCacheLayout = 2;
constexpr char kMagic[8] = {'L', 'D', 'A', 'E', 'O', 'B', 'J', '2'};
constexpr const char *kEntrySuffix = ".ldaeobj";
/// No model's object comes near this; a larger "entry" is not read.
constexpr uint64_t kMaxEntryBytes = 1ull << 30;

/// What precedes the object code in an entry.
struct EntryHeader {
  char magic[8];
  uint64_t size;      // bytes of object code after the header
  uint8_t digest[32]; // SHA-256 of them
  char key[64];       // the entry's key (its file name without suffix)
};

std::string hex(const std::array<uint8_t, 32> &bytes) {
  std::string s;
  char buf[3];
  for (uint8_t b : bytes) {
    std::snprintf(buf, sizeof buf, "%02x", b);
    s += buf;
  }
  return s;
}

bool isHexKey(std::string_view s) {
  return s.size() == 64 &&
         std::all_of(s.begin(), s.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

/// Whether a file's status is one this user's cache wrote: a regular file
/// (not a FIFO, a device or a link), owned by this user and writable by
/// no one else.
bool ownPrivateFile(const struct stat &st) {
  return S_ISREG(st.st_mode) && st.st_uid == ::geteuid() &&
         (st.st_mode & (S_IWGRP | S_IWOTH)) == 0;
}

/// Why the directory cannot be trusted, or "" when it can (or does not
/// exist yet: it is created private on the first write).
std::string untrustedDirectory(const std::string &dir) {
  struct stat st;
  if (::lstat(dir.c_str(), &st) != 0)
    return errno == ENOENT ? "" : std::string("it cannot be read (") +
                                      std::strerror(errno) + ")";
  if (S_ISLNK(st.st_mode))
    return "it is a symbolic link";
  if (!S_ISDIR(st.st_mode))
    return "it is not a directory";
  if (st.st_uid != ::geteuid())
    return "it is owned by another user";
  if (st.st_mode & (S_IWGRP | S_IWOTH))
    return "other users can write to it";
  return "";
}

/// Once per process: each compilation would say it again.
void warnOnce(const std::string &dir, const std::string &why) {
  static std::atomic<bool> warned{false};
  if (warned.exchange(true))
    return;
  llvm::errs() << "ldaec: warning: not using the object cache '" << dir
               << "': " << why
               << "; the model is compiled (docs/codegen.md, \"The object "
                  "cache\")\n";
}

/// The temporary files this cache writes: `.<key>.<pid>.<n>.tmp`.
bool isOwnTemporary(const std::string &name) {
  if (name.size() < 70 || name[0] != '.' || name.substr(65, 1) != "." ||
      !isHexKey(std::string_view(name).substr(1, 64)) ||
      name.compare(name.size() - 4, 4, ".tmp") != 0)
    return false;
  std::string_view middle =
      std::string_view(name).substr(66, name.size() - 70); // "<pid>.<n>"
  size_t dot = middle.find('.');
  auto digits = [](std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
      return c >= '0' && c <= '9';
    });
  };
  return dot != std::string_view::npos && digits(middle.substr(0, dot)) &&
         digits(middle.substr(dot + 1));
}

bool writeAll(int fd, const char *data, size_t size) {
  while (size > 0) {
    ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

} // namespace

ObjectFileCache::ObjectFileCache(std::string dir, const llvm::Module &m,
                                 const llvm::TargetMachine &tm,
                                 const char *optimization)
    : dir_(std::move(dir)) {
  // The key binds an entry to everything its code depends on, with a
  // cryptographic hash: no two inputs share an entry by accident or by
  // design of whoever writes one.
  std::string text;
  llvm::raw_string_ostream os(text);
  os << "ldaec object cache " << kCacheLayout << "; LLVM "
     << LLVM_VERSION_STRING << "; JIT backend " << kJitBackendVersion
     << "; " << tm.getTargetTriple().str() << "; "
     << tm.getTargetCPU() << "; " << tm.getTargetFeatureString() << "; "
     << optimization << "\n";
  m.print(os, nullptr);
  key_ = hex(llvm::SHA256::hash(llvm::ArrayRef(
      reinterpret_cast<const uint8_t *>(text.data()), text.size())));
}

std::string ObjectFileCache::entryPath() const {
  return (fs::path(dir_) / (key_ + kEntrySuffix)).string();
}

bool ObjectFileCache::trusted() const {
  std::string why = untrustedDirectory(dir_);
  if (why.empty())
    return true;
  warnOnce(dir_, why);
  return false;
}

std::unique_ptr<llvm::MemoryBuffer> ObjectFileCache::load() {
  if (!trusted())
    return nullptr;
  // O_NOFOLLOW: no link to /dev/zero or elsewhere; O_NONBLOCK: a FIFO in
  // an entry's place does not hang the open (and fstat refuses it).
  int fd = ::open(entryPath().c_str(),
                  O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
    return nullptr;
  struct stat st;
  std::string bytes;
  bool ok = ::fstat(fd, &st) == 0 && ownPrivateFile(st) &&
            uint64_t(st.st_size) >= sizeof(EntryHeader) &&
            uint64_t(st.st_size) <= kMaxEntryBytes;
  if (ok) {
    bytes.resize(static_cast<size_t>(st.st_size));
    size_t got = 0;
    while (got < bytes.size()) {
      ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
      if (n < 0 && errno == EINTR)
        continue;
      if (n <= 0)
        break;
      got += static_cast<size_t>(n);
    }
    ok = got == bytes.size();
  }
  EntryHeader h;
  if (ok) {
    std::memcpy(&h, bytes.data(), sizeof h);
    llvm::StringRef object = llvm::StringRef(bytes).drop_front(sizeof h);
    std::array<uint8_t, 32> digest = llvm::SHA256::hash(llvm::ArrayRef(
        reinterpret_cast<const uint8_t *>(object.data()), object.size()));
    ok = std::memcmp(h.magic, kMagic, sizeof kMagic) == 0 &&
         std::memcmp(h.key, key_.data(), sizeof h.key) == 0 &&
         h.size == object.size() &&
         std::memcmp(h.digest, digest.data(), sizeof h.digest) == 0;
  }
  // Used now: the last to go when the directory is trimmed.
  if (ok)
    ::futimens(fd, nullptr);
  ::close(fd);
  if (!ok)
    return nullptr;
  return llvm::MemoryBuffer::getMemBufferCopy(
      llvm::StringRef(bytes).drop_front(sizeof h), key_);
}

void ObjectFileCache::notifyObjectCompiled(const llvm::Module *,
                                           llvm::MemoryBufferRef object) {
  // Created private (0700) where it is missing; an existing directory
  // that is not this user's alone is not written to.
  std::error_code ec;
  fs::path dir(dir_);
  if (dir.has_parent_path())
    fs::create_directories(dir.parent_path(), ec);
  if (::mkdir(dir_.c_str(), 0700) != 0 && errno != EEXIST)
    return;
  if (!trusted())
    return;
  EntryHeader h;
  std::memset(&h, 0, sizeof h);
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.size = object.getBufferSize();
  std::array<uint8_t, 32> digest = llvm::SHA256::hash(llvm::ArrayRef(
      reinterpret_cast<const uint8_t *>(object.getBufferStart()), h.size));
  std::memcpy(h.digest, digest.data(), sizeof h.digest);
  std::memcpy(h.key, key_.data(), sizeof h.key);
  // Another process may write the same entry at the same time: each
  // writes its own temporary file (created here, never opened through a
  // name someone else made), and either rename wins whole.
  std::random_device rd;
  fs::path tmp = dir / ("." + key_ + "." + std::to_string(::getpid()) + "." +
                        std::to_string(rd()) + ".tmp");
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW |
                                   O_CLOEXEC,
                  0600);
  if (fd < 0)
    return;
  bool ok = writeAll(fd, reinterpret_cast<const char *>(&h), sizeof h) &&
            writeAll(fd, object.getBufferStart(), h.size);
  ok = ::close(fd) == 0 && ok;
  if (!ok || ::rename(tmp.c_str(), entryPath().c_str()) != 0) {
    fs::remove(tmp, ec);
    return;
  }
  trim();
}

void ObjectFileCache::trim() const {
  // Only what this cache writes, and only this user's: the directory may
  // be any the user named (LDAEC_CACHE_DIR=$PWD must leave thesis.tmp).
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    uint64_t size;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  std::error_code ec;
  const auto staleTmp = fs::file_time_type::clock::now() - std::chrono::hours(24);
  for (fs::directory_iterator it(dir_, ec), end; !ec && it != end;
       it.increment(ec)) {
    const fs::path &p = it->path();
    const std::string name = p.filename().string();
    const bool entry = name.size() == 64 + std::strlen(kEntrySuffix) &&
                       isHexKey(std::string_view(name).substr(0, 64)) &&
                       p.extension() == kEntrySuffix;
    const bool temporary = isOwnTemporary(name);
    struct stat st;
    if ((!entry && !temporary) || ::lstat(p.c_str(), &st) != 0 ||
        !ownPrivateFile(st))
      continue;
    std::error_code e;
    fs::file_time_type used = it->last_write_time(e);
    if (e)
      continue;
    // A temporary file left by a process that died while writing.
    if (temporary) {
      if (used < staleTmp)
        fs::remove(p, e);
      continue;
    }
    entries.push_back({p, used, uint64_t(st.st_size)});
    total += uint64_t(st.st_size);
  }
  if (total <= kMaxCacheBytes)
    return;
  std::sort(entries.begin(), entries.end(),
            [](const Entry &a, const Entry &b) { return a.used < b.used; });
  for (const Entry &e : entries) {
    if (total <= kMaxCacheBytes)
      break;
    std::error_code rm;
    if (fs::remove(e.path, rm))
      total -= e.size;
  }
}

} // namespace ldae::codegen
