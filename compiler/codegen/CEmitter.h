// The C99 emitter: prints a code plan as one self-contained C file.
#pragma once

#include "codegen/CodePlan.h"

#include <string>

namespace ldae::codegen {

/// The C file of `plan`; with `withMain`, also a `main` integrating the
/// model with IDA and writing CSV (see docs/embedding-c.md).
std::string printC(const CodePlan &plan, bool withMain);

} // namespace ldae::codegen
