// LLVM IR emission from a code plan, the O2 pipeline, and the ORC LLJIT
// backend that turns the plan into machine code behind the C ABI.
#pragma once

#include "codegen/CodePlan.h"
#include "support/Expected.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace llvm {
class LLVMContext;
class Module;
class TargetMachine;
} // namespace llvm

namespace ldae::codegen {

/// The exported symbol of plan function `fn`: "<symbolName>_<fn.name>".
std::string functionSymbol(const CodePlan &plan, const PlanFunction &fn);

/// A module defining every plan function with its C ABI signature (chunks
/// as internal, non-inlined helpers).
std::unique_ptr<llvm::Module> emitModule(const CodePlan &plan,
                                         llvm::LLVMContext &ctx);

/// Runs the standard O2 pipeline for `tm` on `m`.
void optimizeModule(llvm::Module &m, llvm::TargetMachine &tm, bool full = true);

/// Code compiled by the JIT, alive as long as this object.
class JitCode {
public:
  virtual ~JitCode();
  /// Address of plan function i.
  virtual uintptr_t address(int i) const = 0;
};

/// Emits, optimizes and JIT-compiles every function of `plan`.
Expected<std::unique_ptr<JitCode>> jitCompile(const CodePlan &plan);

/// The optimized module of `plan` as LLVM assembly text (`--emit llvm`).
std::string printModule(const CodePlan &plan);

} // namespace ldae::codegen
