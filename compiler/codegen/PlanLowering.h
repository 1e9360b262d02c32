// Lowering an index-1 DaeSystem into the code plan (CodePlan.h): the one
// step between the IR and every backend, so the JIT, the interpreter and
// the C printer compute the same operations in the same order.
#pragma once

#include "codegen/CodePlan.h"
#include "ir/DaeSystem.h"
#include "support/Expected.h"

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

struct PlanOptions {
  /// Non-leaf nodes per chunk (machine function).
  unsigned chunkSize = 256;
  /// Roll repeated stores into loops (functions with at least
  /// kLoopMinStores stores; see rollLoops).
  bool loops = true;
  /// Resolves residual locations to "file:line" (optional).
  const SourceManager *sources = nullptr;
};

/// Lowers `sys` (validated against the layout rule) into a code plan,
/// differentiating residuals for the Jacobians. Fails when an expression
/// reads a variable that is not in the unknown layout.
Expected<CodePlan> lowerToPlan(const ir::DaeSystem &sys,
                               const PlanOptions &opts = {});

} // namespace ldae::codegen
