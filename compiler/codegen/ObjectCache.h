// The JIT's object cache: the machine code of each compiled model kept as
// a file in a directory (CodegenOptions::cacheDir), so the next run of an
// unchanged model loads it instead of optimizing and compiling again
// (docs/codegen.md, "The object cache"). Built into the JIT module only.
//
// An entry's name is the SHA-256 of everything the machine code depends
// on: the module's IR before optimization, the target (triple, CPU,
// features), the optimization level, and the versions of LLVM, of the JIT
// backend and of this file's layout. An entry is written to a temporary
// file and renamed into place, so a reader never sees half of one; one
// that does not read back whole (truncated, another layout, a SHA-256
// that does not match) is ignored and written again. The directory is kept
// under kMaxCacheBytes by removing the entries used least recently.
//
// The cache is a trust boundary (docs/codegen.md, "Threat model"): its
// entries are machine code this process runs. A directory that is not
// this user's alone (another owner, writable by others, a symbolic link)
// is not used at all, with a warning once; an entry that is not a regular
// file of this user's that no one else can write is not read; the
// directory is created 0700; the trim removes only files of the cache's
// own names and this user's.
#pragma once

#include "llvm/ExecutionEngine/ObjectCache.h"

#include <cstdint>
#include <memory>
#include <string>

namespace llvm {
class MemoryBuffer;
class Module;
class TargetMachine;
} // namespace llvm

namespace ldae::codegen {

/// The cache directory is trimmed to this many bytes of entries.
inline constexpr uint64_t kMaxCacheBytes = 200ull << 20;

class ObjectFileCache : public llvm::ObjectCache {
public:
  /// `dir` is created when the first entry is written.
  ObjectFileCache(std::string dir, const llvm::Module &m,
                  const llvm::TargetMachine &tm, const char *optimization);

  /// The object stored for the module, or null (absent or unusable); a
  /// hit marks the entry as recently used.
  std::unique_ptr<llvm::MemoryBuffer> load();

  /// Stores the object compiled for the module (ORC calls it after code
  /// generation). A failure to write leaves the run as it is: the cache
  /// only saves time.
  void notifyObjectCompiled(const llvm::Module *m,
                            llvm::MemoryBufferRef object) override;
  /// Not consulted: load() runs before optimization, which a hit skips.
  std::unique_ptr<llvm::MemoryBuffer>
  getObject(const llvm::Module *) override {
    return nullptr;
  }

  const std::string &dir() const { return dir_; }
  const std::string &key() const { return key_; }

private:
  std::string entryPath() const;
  /// Whether the directory may be used (see the file comment); warns once
  /// per process when not.
  bool trusted() const;
  /// Removes the least recently used entries above kMaxCacheBytes.
  void trim() const;

  std::string dir_, key_;
};

} // namespace ldae::codegen
