// Public entry of code generation: turns a DaeSystem into a live ldae_model
// (LLVM JIT or interpreter) or into text (LLVM IR, C99). All paths go
// through one lowering (CodePlan.h), so they compute the same thing.
#pragma once

#include "ir/DaeSystem.h"
#include "ldae/model.h"
#include "support/Expected.h"

#include <memory>
#include <optional>
#include <string>

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

/// `--jit auto` compiles with LLVM above this many operations per
/// evaluation (planWork). Below it, loading LLVM and compiling costs more
/// than the interpreter loses over a whole run; measured by
/// bench/startup.py (docs/codegen.md, "Choosing the backend").
constexpr size_t kAutoJitWork = 20000;

struct CodegenOptions {
  /// The backend (`--jit on|off|auto`): true the LLVM ORC JIT, false the
  /// plan interpreter, unset the interpreter up to kAutoJitWork operations
  /// per evaluation and the JIT above.
  std::optional<bool> jit = true;
  /// Non-leaf operations per machine function (bounds compile time).
  unsigned chunkSize = 256;
  /// Compile repeated equations as loops (CodePlan.h, rollLoops).
  bool loops = true;
  /// Resolves residual locations for ldae_model::residual_origin.
  const SourceManager *sources = nullptr;
  /// The JIT keeps the object code of each compiled model here, keyed by
  /// its content and these options, and loads it instead of compiling
  /// when it is there (docs/codegen.md, "The object cache"). "": no cache.
  std::string cacheDir;
};

/// The backend a model got, and why (`--stats`).
struct BackendChoice {
  bool jit = false;
  bool automatic = false; // chosen by size (`--jit auto`)
  size_t work = 0;        // planWork
  /// The JIT's object cache: "" unused, else "hit" or "miss".
  std::string cache;
  std::string cacheDir;
};

/// One line for `--stats`: "backend: interpreter (--jit auto: 97
/// operations per evaluation, the JIT above 20000)"; a JIT with the object
/// cache adds a second line: "object cache: hit (/dir)".
std::string describeBackend(const BackendChoice &choice);

/// Owns the compiled code and every array the ldae_model points into.
class CompiledModel {
public:
  virtual ~CompiledModel();
  virtual const ldae_model &model() const = 0;
  const BackendChoice &backend() const { return backend_; }

protected:
  BackendChoice backend_;
};

/// Compiles `sys`; fails when the system breaks the layout rule (a variable
/// that is no unknown), or when LLVM fails.
Expected<std::unique_ptr<CompiledModel>>
compile(const ir::DaeSystem &sys, const CodegenOptions &opts = {});

/// `--emit llvm`: the optimized LLVM module (or an error message); loads
/// the JIT module (JitBackend.h).
Expected<std::string> emitLlvm(const ir::DaeSystem &sys,
                               const CodegenOptions &opts = {});

/// A mode of a variable-structure model to compile ahead: its mode values
/// (ir::EventSystem::modeDiscrete order) and its reduced system.
struct ModeSystem {
  std::vector<double> values;
  const ir::DaeSystem *system = nullptr;
};

/// `--emit c [--main]`: one self-contained C99 file; with `withMain` also a
/// `main` handing the model to the runtime's ldae_main (libldaert), which
/// runs it as `ldaec --simulate` does (docs/embedding-c.md). The `modes` of
/// a variable-structure model are compiled into it ahead.
Expected<std::string> emitC(const ir::DaeSystem &sys, bool withMain,
                            const CodegenOptions &opts = {},
                            const std::vector<ModeSystem> &modes = {});

} // namespace ldae::codegen
