// The C99 emitter: prints a code plan as one self-contained C file.
#pragma once

#include "codegen/CodePlan.h"

#include <string>
#include <vector>

namespace ldae::codegen {

/// A mode of a variable-structure model compiled ahead: the mode values
/// (ir::EventSystem::modeDiscrete order) and its plan.
struct ModePlan {
  std::vector<double> values;
  CodePlan plan;
};

/// The C file of `plan`; with `withMain`, also a `main` running the model
/// with the runtime's ldae_main (libldaert; see docs/embedding-c.md). The
/// `modes` of a variable-structure model go into its table of modes
/// compiled ahead (ldae_model's ABI 12 block), their symbols made unique.
std::string printC(const CodePlan &plan, bool withMain,
                   const std::vector<ModePlan> &modes = {});

} // namespace ldae::codegen
