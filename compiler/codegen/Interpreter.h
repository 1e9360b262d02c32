// The interpreter backend (`--jit off`): evaluates plan functions node by
// node. It is the reference the JIT and the emitted C are tested against.
//
// The C ABI's functions take no user-data pointer, so each interpreted
// function occupies one slot of a process-wide table of fixed thunks (a
// bounded number, kInterpreterSlots); the slots are released when the
// compiled model is destroyed.
#pragma once

#include "codegen/CodePlan.h"
#include "support/Expected.h"

#include <cstdint>
#include <vector>

namespace ldae::codegen {

/// Evaluates `fn` (outputs to out0/out1 per its stores). Returns 0, or
/// 1 + row of the first store whose value hit a domain error.
int interpret(const PlanFunction &fn, double t, const double *y,
              const double *yp, const double *p, double cj, double *out0,
              double *out1);

/// Thunk slots available to interpreted functions at the same time.
constexpr unsigned kInterpreterSlots = 1024;

/// Binds `fn` (which must outlive the binding) to a free slot and returns
/// the address of a C-ABI function for its signature.
Expected<uintptr_t> bindInterpreterSlot(const PlanFunction &fn,
                                        unsigned &slot);
void releaseInterpreterSlot(unsigned slot);

} // namespace ldae::codegen
