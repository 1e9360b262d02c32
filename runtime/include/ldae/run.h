/* The runtime's C entry point: the whole `main` of a program that
 * `ldaec --emit c --main` writes. It parses the program's command line,
 * re-evaluates what a changed parameter binds, runs the same simulation as
 * `ldaec --simulate` (consistent initialization, state-set switching, IDA
 * or CVODE, the failure report) and writes the same CSV. Implemented in C++
 * (runtime/src/CMain.cpp) and shipped as the shared library libldaert, so a
 * C program needs only this header, the model and `-lldaert`
 * (docs/embedding-c.md).
 *
 * Plain C99. The emitted file inlines this header after ldae/model.h, so
 * it includes model.h only when that is not already there.
 */
#ifndef LDAE_RUN_H
#define LDAE_RUN_H

#ifndef LDAE_MODEL_H
#include "ldae/model.h"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* out = the bindings of the bound parameters, then the start values that
   read parameters, each evaluated over p (see ldae_bindings). */
typedef int (*ldae_bind_fn)(double t, const double *y, const double *yp,
                            const double *p, double *out);

/* What a parameter given on the command line changes besides itself. All
   arrays are indices; NULL is fine where the count is 0. */
typedef struct ldae_bindings {
  ldae_bind_fn bind;           /* NULL when nothing is bound */
  int n_bound_params;
  const int *bound_params;     /* parameters with a binding (k2 = 3*k) */
  int n_bound_starts;
  const int *bound_starts;     /* unknowns whose start value reads p */
  int bind_passes;             /* passes that settle chains of bindings */
  const int *structural;       /* n_params: 1 when the value fixed the
                                  model's structure (cannot change); may
                                  be NULL (none) */
} ldae_bindings;

/* Runs the program: `argc`/`argv` as main received them, `bindings` may be
   NULL (no parameter reads another). Returns the exit code: 0 success,
   1 an internal error (out of memory, the CSV could not be written),
   2 bad command line (nothing done), 3 numerical failure (the rows up to
   it are written). */
int ldae_main(const ldae_model *model, const ldae_bindings *bindings, int argc,
              char **argv);

#ifdef __cplusplus
}
#endif

#endif /* LDAE_RUN_H */
