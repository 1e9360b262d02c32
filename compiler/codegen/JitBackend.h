// The seam between code generation and its LLVM backend. The backend lives
// in a module of its own, libldae_jit.so, loaded on first use: a run that
// does not JIT (the interpreter, --emit c) never loads the 129 MB libLLVM
// and the libraries it pulls in, which was a third of the start-up time of
// a small model (docs/codegen.md, "Start-up").
//
// Both sides are built from the same sources by the same compiler, so the
// table below passes C++ types; the module still states the version and
// the plan layout it was built with, and a stale module is refused.
#pragma once

#include "codegen/CodePlan.h"
#include "support/Expected.h"

#include <cstdint>
#include <memory>
#include <string>

namespace ldae::codegen {

/// What the object cache (ObjectCache.h) did for one model.
enum class CacheUse { None, Hit, Miss };

/// Code compiled by the JIT, alive as long as this object.
class JitCode {
public:
  virtual ~JitCode() = default;
  /// Address of plan function i.
  virtual uintptr_t address(int i) const = 0;
  /// Hit: loaded from the object cache, no optimization or code generation.
  CacheUse cache = CacheUse::None;
};

/// Bumped when this table or the meaning of a plan changes.
inline constexpr unsigned kJitBackendVersion = 3;

/// What the module exports through its one C symbol, kJitEntrySymbol.
struct JitBackend {
  unsigned version = kJitBackendVersion;
  size_t planSize = sizeof(CodePlan);
  size_t functionSize = sizeof(PlanFunction);
  /// `cacheDir`: the object cache's directory ("": none).
  Expected<std::unique_ptr<JitCode>> (*compile)(const CodePlan &plan,
                                                const std::string &cacheDir) =
      nullptr;
  std::string (*print)(const CodePlan &plan) = nullptr;
};

inline constexpr const char *kJitModuleName = "libldae_jit.so";
inline constexpr const char *kJitEntrySymbol = "ldae_jit_backend";
using JitEntry = const JitBackend *(*)();

/// The backend, its module loaded on first use: from $LDAEC_JIT_MODULE when
/// set, else beside the executable, else in ../lib/ldaec/ from it, else in
/// the build tree. Fails saying where it looked and why it failed.
Expected<const JitBackend *> loadJitBackend();

/// Emits, optimizes and JIT-compiles every function of `plan`, or loads
/// the machine code from the object cache in `cacheDir` ("": no cache).
Expected<std::unique_ptr<JitCode>> jitCompile(const CodePlan &plan,
                                              const std::string &cacheDir = "");

/// The optimized module of `plan` as LLVM assembly text (`--emit llvm`).
Expected<std::string> printModule(const CodePlan &plan);

} // namespace ldae::codegen
