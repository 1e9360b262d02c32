// The C99 emitter: prints a code plan as one self-contained C file.
#pragma once

#include "codegen/CodePlan.h"

#include <string>

namespace ldae::codegen {

/// The C file of `plan`; with `withMain`, also a `main` running the model
/// with the runtime's ldae_main (libldaert; see docs/embedding-c.md).
std::string printC(const CodePlan &plan, bool withMain);

} // namespace ldae::codegen
