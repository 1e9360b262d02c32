// The JIT's object cache; see ObjectCache.h.
#include "codegen/ObjectCache.h"

#include "codegen/JitBackend.h"

#include "llvm/Config/llvm-config.h"
#include "llvm/IR/Module.h"
#include "llvm/Support/MemoryBuffer.h"
#include "llvm/Support/raw_ostream.h"
#include "llvm/Support/xxhash.h"
#include "llvm/Target/TargetMachine.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>
#include <vector>

namespace ldae::codegen {

namespace {

namespace fs = std::filesystem;

/// Bumped when the entry layout or what the key covers changes.
constexpr unsigned kCacheLayout = 1;
constexpr char kMagic[8] = {'L', 'D', 'A', 'E', 'O', 'B', 'J', '1'};
constexpr const char *kEntrySuffix = ".ldaeobj";

/// What precedes the object code in an entry.
struct EntryHeader {
  char magic[8];
  uint64_t size;     // bytes of object code after the header
  uint64_t checksum; // xxh3_64 of them
  char key[32];      // the entry's key (its file name without suffix)
};

std::string hex128(llvm::XXH128_hash_t h) {
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx",
                static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return buf;
}

} // namespace

ObjectFileCache::ObjectFileCache(std::string dir, const llvm::Module &m,
                                 const llvm::TargetMachine &tm,
                                 bool fullOptimization)
    : dir_(std::move(dir)) {
  std::string text;
  llvm::raw_string_ostream os(text);
  os << "ldaec object cache " << kCacheLayout << "; LLVM "
     << LLVM_VERSION_STRING << "; JIT backend " << kJitBackendVersion
     << "; " << tm.getTargetTriple().str() << "; "
     << tm.getTargetCPU() << "; " << tm.getTargetFeatureString() << "; "
     << (fullOptimization ? "O2" : "O1") << "\n";
  m.print(os, nullptr);
  key_ = hex128(llvm::xxh3_128bits(
      llvm::ArrayRef(reinterpret_cast<const uint8_t *>(text.data()),
                     text.size())));
}

std::string ObjectFileCache::entryPath() const {
  return (fs::path(dir_) / (key_ + kEntrySuffix)).string();
}

std::unique_ptr<llvm::MemoryBuffer> ObjectFileCache::load() {
  auto file = llvm::MemoryBuffer::getFile(entryPath(), /*IsText=*/false,
                                          /*RequiresNullTerminator=*/false);
  if (!file)
    return nullptr;
  llvm::StringRef bytes = (*file)->getBuffer();
  EntryHeader h;
  if (bytes.size() < sizeof h)
    return nullptr;
  std::memcpy(&h, bytes.data(), sizeof h);
  llvm::StringRef object = bytes.drop_front(sizeof h);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 ||
      std::memcmp(h.key, key_.data(), sizeof h.key) != 0 ||
      h.size != object.size() || h.checksum != llvm::xxh3_64bits(object))
    return nullptr;
  // Used now: the last to go when the directory is trimmed.
  std::error_code ec;
  fs::last_write_time(entryPath(), fs::file_time_type::clock::now(), ec);
  return llvm::MemoryBuffer::getMemBufferCopy(object, key_);
}

void ObjectFileCache::notifyObjectCompiled(const llvm::Module *,
                                           llvm::MemoryBufferRef object) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    return;
  EntryHeader h;
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.size = object.getBufferSize();
  h.checksum = llvm::xxh3_64bits(object.getBuffer());
  std::memcpy(h.key, key_.data(), sizeof h.key);
  // Another process may write the same entry at the same time: each
  // writes its own temporary file, and either rename wins whole.
  std::random_device rd;
  fs::path tmp = fs::path(dir_) / ("." + key_ + "." + std::to_string(::getpid()) +
                                   "." + std::to_string(rd()) + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char *>(&h), sizeof h);
    out.write(object.getBufferStart(), std::streamsize(h.size));
    out.close();
    if (!out) {
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, entryPath(), ec);
  if (ec) {
    fs::remove(tmp, ec);
    return;
  }
  trim();
}

void ObjectFileCache::trim() const {
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
    std::error_code e;
    fs::file_time_type used = it->last_write_time(e);
    if (e)
      continue;
    // A temporary file left by a process that died while writing.
    if (p.extension() == ".tmp" && used < staleTmp) {
      fs::remove(p, e);
      continue;
    }
    if (p.extension() != kEntrySuffix)
      continue;
    uint64_t size = it->file_size(e);
    if (e)
      continue;
    entries.push_back({p, used, size});
    total += size;
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
