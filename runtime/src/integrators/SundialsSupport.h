// What the IDA and CVODE wrappers share: the error of a failed set-up
// call, the message handler, the CSC pattern copy, and the getters' common
// shapes.
#pragma once

#include "integrators/Integrator.h"

#include <fmt/format.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace ldae::runtime::sundials {

inline Error callError(const char *call, int flag) {
  return Error{
      fmt::format("internal error: {} failed with flag {}", call, flag)};
}

/// Returns the Error of a SUNDIALS set-up call that failed.
#define LDAE_SUNDIALS_CHECK(call)                                              \
  do {                                                                         \
    int flag_ = (call);                                                        \
    if (flag_ < 0)                                                             \
      return ::ldae::runtime::sundials::callError(#call, flag_);               \
  } while (0)

/// The error handler of both solvers: keeps the last message for the
/// failure report instead of printing it.
inline void keepMessage(int code, const char *, const char *function,
                        char *msg, void *user) {
  auto *d = static_cast<Integrator::CallbackData *>(user);
  d->message = fmt::format("{} ({}): {}", function, code, msg);
}

/// Writes state set `s`'s CSC pattern into the sparse matrix J.
inline void copyPattern(SUNMatrix J, const ldae_state_set &s, int n) {
  sunindextype *colptr = SUNSparseMatrix_IndexPointers(J);
  sunindextype *rowind = SUNSparseMatrix_IndexValues(J);
  for (int c = 0; c <= n; ++c)
    colptr[c] = s.jac_colptr[c];
  for (int q = 0; q < s.jac_nnz; ++q)
    rowind[q] = s.jac_rowind[q];
}

/// |w_i e_i| from a solver's getters of error weights and estimated local
/// errors (zeros where they fail, and before the solver's first step,
/// whose error vectors are still uninitialized memory: a failed
/// initialization listed a different "weighted error 9.48e-310" each run).
template <typename GetWeights, typename GetErrors>
std::vector<double> weightedErrors(N_Vector like, int n, long steps,
                                   GetWeights weights, GetErrors errors) {
  std::vector<double> out(n, 0.0);
  if (steps <= 0)
    return out;
  N_Vector w = N_VClone(like), e = N_VClone(like);
  if (w && e && weights(w) >= 0 && errors(e) >= 0) {
    const double *pw = N_VGetArrayPointer(w), *pe = N_VGetArrayPointer(e);
    for (int i = 0; i < n; ++i)
      out[i] = std::abs(pw[i] * pe[i]);
  }
  if (w)
    N_VDestroy(w);
  if (e)
    N_VDestroy(e);
  return out;
}

/// A getter's value, 0 when it fails (only on a missing memory block).
template <typename Get> double valueOrZero(Get get) {
  double v = 0;
  return get(&v) < 0 ? 0 : v;
}

/// The root components found at the last root return (zeros on failure).
template <typename GetInfo>
std::vector<int> rootInfo(int nRoots, GetInfo info) {
  std::vector<int> found(std::max(nRoots, 0));
  if (!found.empty() && info(found.data()) < 0)
    found.assign(found.size(), 0);
  return found;
}

} // namespace ldae::runtime::sundials
