// External functions (MLS 12.9) as the IR sees them: a process-wide,
// append-only table of callable entries. Every entry is a wrapper with one
// signature, `void f(const double *in, double *out)`, generated beside the
// user's C (frontend/ExternalFunctions.cpp): it converts the flattened
// doubles to the declared C types, calls the function and writes all its
// outputs. One signature keeps the IR, the evaluator and every backend free
// of C type knowledge. The table is process-wide because the shared objects
// holding the entries are.
#pragma once

#include "ir/Expr.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ldae::ir {

using ExternalEntry = void (*)(const double *in, double *out);

struct ExternalFunction {
  std::string name;   // the Modelica name, for messages
  std::string symbol; // the wrapper's C symbol (unique per wrapper text)
  unsigned numInputs = 0, numOutputs = 0; // doubles in, doubles out
  bool impure = false;
  /// An external object's constructor (MLS 12.9.7): its result is a handle
  /// valid in the process that made it, so a program that runs the model
  /// elsewhere (--emit c) makes it again (codegen/PlanLowering.cpp).
  bool constructor = false;
  ExternalEntry entry = nullptr;
  /// The shared objects to link for the entry, in load order (each one's
  /// symbols before the ones that use them), the wrapper's last.
  std::vector<std::string> objects;
};

/// Registers `f` (or finds the entry with its symbol) and returns its id.
uint32_t registerExternal(const ExternalFunction &f);
/// The entry with id `id`; stable for the life of the process.
const ExternalFunction &externalFunction(uint32_t id);
/// Whether any entry is registered (no External node exists without one).
bool anyExternal();
/// Whether `e` is a call of an external object's constructor: the binding
/// of a handle that a program of its own (--emit c) can make again.
bool isConstructorCall(ExprRef e);
/// Calls entry `id` on `in` and returns output `output`.
double callExternal(uint32_t id, const double *in, unsigned output);

} // namespace ldae::ir
