// Public entry of code generation: turns a DaeSystem into a live ldae_model
// (LLVM JIT or interpreter) or into text (LLVM IR, C99). All paths go
// through one lowering (CodePlan.h), so they compute the same thing.
#pragma once

#include "ir/DaeSystem.h"
#include "ldae/model.h"
#include "support/Expected.h"

#include <memory>
#include <string>

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

struct CodegenOptions {
  /// LLVM ORC JIT when true; the plan interpreter (`--jit off`) otherwise.
  bool jit = true;
  /// Non-leaf operations per machine function (bounds compile time).
  unsigned chunkSize = 256;
  /// Compile repeated equations as loops (CodePlan.h, rollLoops).
  bool loops = true;
  /// Resolves residual locations for ldae_model::residual_origin.
  const SourceManager *sources = nullptr;
};

/// Owns the compiled code and every array the ldae_model points into.
class CompiledModel {
public:
  virtual ~CompiledModel();
  virtual const ldae_model &model() const = 0;
};

/// Compiles `sys`; fails when the system breaks the layout rule (a variable
/// that is no unknown), or when LLVM fails.
Expected<std::unique_ptr<CompiledModel>>
compile(const ir::DaeSystem &sys, const CodegenOptions &opts = {});

/// `--emit llvm`: the optimized LLVM module (or an error message).
Expected<std::string> emitLlvm(const ir::DaeSystem &sys,
                               const CodegenOptions &opts = {});

/// `--emit c [--main]`: one self-contained C99 file; with `withMain` also a
/// `main` handing the model to the runtime's ldae_main (libldaert), which
/// runs it as `ldaec --simulate` does (docs/embedding-c.md).
Expected<std::string> emitC(const ir::DaeSystem &sys, bool withMain,
                            const CodegenOptions &opts = {});

} // namespace ldae::codegen
