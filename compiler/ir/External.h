// External functions (MLS 12.9) as the IR sees them: a process-wide,
// append-only table of callable entries. Every entry is a wrapper with one
// signature, `void f(const double *in, double *out)`, generated beside the
// user's C (frontend/ExternalFunctions.cpp): it converts the flattened
// doubles to the declared C types, calls the function and writes all its
// outputs. One signature keeps the IR, the evaluator and every backend free
// of C type knowledge. The table is process-wide because the shared objects
// holding the entries are.
#pragma once

#include <cstdint>
#include <string>

namespace ldae::ir {

using ExternalEntry = void (*)(const double *in, double *out);

struct ExternalFunction {
  std::string name;   // the Modelica name, for messages
  std::string symbol; // the wrapper's C symbol (unique per wrapper text)
  unsigned numInputs = 0, numOutputs = 0; // doubles in, doubles out
  bool impure = false;
  ExternalEntry entry = nullptr;
};

/// Registers `f` (or finds the entry with its symbol) and returns its id.
uint32_t registerExternal(const ExternalFunction &f);
/// The entry with id `id`; stable for the life of the process.
const ExternalFunction &externalFunction(uint32_t id);
/// Whether any entry is registered (no External node exists without one).
bool anyExternal();
/// Calls entry `id` on `in` and returns output `output`.
double callExternal(uint32_t id, const double *in, unsigned output);

} // namespace ldae::ir
