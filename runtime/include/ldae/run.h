/* The runtime's C entry point: the whole `main` of a program that
 * `ldaec --emit c --main` writes. It parses the program's command line,
 * re-evaluates what a changed parameter binds, runs the same simulation as
 * `ldaec --simulate` (consistent initialization, state-set switching, IDA
 * or CVODE, the failure report) and writes the same CSV. Implemented in C++
 * (runtime/src/cmain/CMain.cpp) and shipped as the shared library libldaert, so a
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

/* Runs the program: `argc`/`argv` as main received them. What a changed
   parameter binds comes from the model (its run-time parameters block).
   Returns the exit code: 0 success,
   1 an internal error (out of memory, the CSV could not be written),
   2 bad command line (nothing done), 3 numerical failure (the rows up to
   it are written). */
int ldae_main(const ldae_model *model, int argc, char **argv);

#ifdef __cplusplus
}
#endif

#endif /* LDAE_RUN_H */
