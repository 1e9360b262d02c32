// LLVM IR emission from a code plan, the O2 pipeline, and the ORC LLJIT
// backend that turns the plan into machine code behind the C ABI. Compiled
// into the JIT module only (JitBackend.h): nothing else links LLVM.
#pragma once

#include "codegen/JitBackend.h"

#include <memory>

namespace llvm {
class LLVMContext;
class Module;
class TargetMachine;
} // namespace llvm

namespace ldae::codegen {

/// A module defining every plan function with its C ABI signature (chunks
/// as internal, non-inlined helpers).
std::unique_ptr<llvm::Module> emitModule(const CodePlan &plan,
                                         llvm::LLVMContext &ctx);

/// How hard LLVM works on a module: by the plan's size (docs/codegen.md).
enum class OptTier { O2, O1, O0 };
const char *optTierName(OptTier tier);

/// Runs the standard pipeline of `tier` for `tm` on `m` (none for O0).
void optimizeModule(llvm::Module &m, llvm::TargetMachine &tm,
                    OptTier tier = OptTier::O2);

/// The backend's table (what the module's kJitEntrySymbol returns).
const JitBackend &llvmBackend();

} // namespace ldae::codegen
