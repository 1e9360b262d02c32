// Building and loading the C code of external functions (MLS 12.9): a
// translation unit ldaec generates, plus C source files of the user's
// library, compiled by the system C compiler into a shared object that is
// loaded into this process. Built objects are kept in the user's cache
// directory under the trust rules of the JIT's object cache (docs/codegen.md,
// "External C code"): they are code this process runs.
#pragma once

#include "support/Expected.h"

#include <string>
#include <vector>

namespace ldae::frontend {

/// The system C compiler: Debian's `cc` (gcc), by absolute path.
inline constexpr const char *kCCompiler = "/usr/bin/cc";

struct CBuild {
  std::string source; // the generated translation unit
  std::vector<std::string> files;       // C sources compiled with it
  std::vector<std::string> includeDirs; // -I
  std::vector<std::string> libraries;   // -l, after the sources
  std::vector<std::string> defines;     // -D
};

/// The C text of ldaec's ModelicaUtilities.h callbacks (ModelicaError...),
/// built into a shared object of its own that is loaded before any
/// library that calls them.
const char *modelicaUtilitiesSource();

/// A shared object built and loaded.
struct LoadedC {
  void *handle = nullptr; // dlopen's
  std::string path;       // the file: what an emitted program links
};

/// Builds `build` into a shared object, or finds it in `cacheDir` (a key
/// over the sources, the flags and the compiler), and loads it with its
/// symbols global (a later object may use them). An error carries the
/// compiler's first messages.
Expected<LoadedC> loadCBuild(const CBuild &build, const std::string &cacheDir);

/// The SHA-256 of `data` in hex (cache keys, unique C symbol names).
std::string sha256Hex(const std::string &data);

} // namespace ldae::frontend
