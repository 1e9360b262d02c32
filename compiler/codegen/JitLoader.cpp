// Finds and loads the JIT module (JitBackend.h) the first time a model is
// JIT-compiled, and forwards to it. The executable links no LLVM, so a run
// that never gets here never maps libLLVM.
#include "codegen/JitBackend.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

namespace ldae::codegen {
namespace {

namespace fs = std::filesystem;

/// The directory of the running executable ("" if /proc is unavailable).
fs::path executableDir() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

/// Where the module may be, in the order searched (JitBackend.h).
std::vector<fs::path> candidatePaths() {
  std::vector<fs::path> paths;
  if (fs::path dir = executableDir(); !dir.empty()) {
    paths.push_back(dir / kJitModuleName);
    paths.push_back(dir.parent_path() / "lib" / "ldaec" / kJitModuleName);
  }
#ifdef LDAE_JIT_MODULE_BUILD_PATH
  // Unit tests and benchmarks link codegen from their own directories.
  paths.push_back(LDAE_JIT_MODULE_BUILD_PATH);
#endif
  return paths;
}

Expected<const JitBackend *> openModule(const fs::path &path) {
  void *handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle)
    return Error{"cannot load the LLVM JIT module: " + std::string(dlerror())};
  auto entry = reinterpret_cast<JitEntry>(dlsym(handle, kJitEntrySymbol));
  const JitBackend *backend = entry ? entry() : nullptr;
  JitBackend expected;
  if (!backend || backend->version != expected.version ||
      backend->planSize != expected.planSize ||
      backend->functionSize != expected.functionSize) {
    // Kept loaded: unloading LLVM's static state is not worth the risk.
    return Error{"the LLVM JIT module '" + path.string() +
                 "' is from another build of ldaec; rebuild or reinstall it"};
  }
  return backend;
}

Expected<const JitBackend *> findModule() {
  if (const char *env = std::getenv("LDAEC_JIT_MODULE"); env && *env)
    return openModule(env);
  std::string looked;
  for (const fs::path &p : candidatePaths()) {
    std::error_code ec;
    if (fs::exists(p, ec))
      return openModule(p);
    looked += (looked.empty() ? "" : ", ") + p.string();
  }
  return Error{"the LLVM JIT module " + std::string(kJitModuleName) +
               " was not found (looked in " + looked +
               "); --jit off runs the model without it"};
}

} // namespace

Expected<const JitBackend *> loadJitBackend() {
  static const Expected<const JitBackend *> backend = findModule();
  return backend;
}

Expected<std::unique_ptr<JitCode>> jitCompile(const CodePlan &plan,
                                              const std::string &cacheDir) {
  auto backend = loadJitBackend();
  if (!backend)
    return Error{backend.error()};
  return (*backend)->compile(plan, cacheDir);
}

Expected<std::string> printModule(const CodePlan &plan) {
  auto backend = loadJitBackend();
  if (!backend)
    return Error{backend.error()};
  return (*backend)->print(plan);
}

} // namespace ldae::codegen
