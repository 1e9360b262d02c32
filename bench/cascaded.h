/* ScalableTestSuite's CascadedFirstOrder for the hand-written reference
 * programs (cascaded_ida.c with IDA + KLU, cascaded_cvode.c with CVODE BDF
 * + KLU), set up as ldaec runs tests/models/cascaded_first_order.lsd:
 *
 *   x'[1] = (1 - x[1]) / tau,  x'[i] = (x[i-1] - x[i]) / tau,  i = 2..N,
 *   x(0) = 0,  tau = T / N,  T = 1,
 *
 * rtol 1e-6 (the experiment's Tolerance), atol = rtol (ldaec's default, all
 * nominal values 1), output at start + k * interval with interval
 * (stop - start) / 500 and the last row exactly at stop, every unknown
 * copied into a row buffer at each output time as ldaec records it.
 *
 * Usage: PROGRAM N [--rtol R] [--atol A] [--stop T] [--interval H]
 * Prints "time,x[N]" at every output time on stdout (a CSV, for the
 * closed-form check) and the statistics on stderr. */
#ifndef LDAE_BENCH_CASCADED_H
#define LDAE_BENCH_CASCADED_H

#include "sundials_bench.h"

#include <sundials/sundials_types.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <math.h>
#include <string.h>

typedef struct {
  long n;
  double tau, rtol, atol, stop, interval;
  long rows;     /* output rows after the start row */
  double *saved; /* (rows + 1) x n recorded values */
} Cascaded;

static inline double cascadedOption(int argc, char **argv, const char *name,
                                    double dflt) {
  for (int i = 2; i + 1 < argc; ++i)
    if (strcmp(argv[i], name) == 0)
      return atof(argv[i + 1]);
  return dflt;
}

static inline Cascaded cascadedSetup(int argc, char **argv) {
  Cascaded c;
  if (argc < 2 || atol(argv[1]) < 1) {
    fprintf(stderr,
            "usage: %s N [--rtol R] [--atol A] [--stop T] "
            "[--interval H]\n",
            argv[0]);
    exit(2);
  }
  c.n = atol(argv[1]);
  c.tau = 1.0 / (double)c.n;
  c.rtol = cascadedOption(argc, argv, "--rtol", 1e-6);
  c.atol = cascadedOption(argc, argv, "--atol", c.rtol);
  c.stop = cascadedOption(argc, argv, "--stop", 2.0);
  c.interval = cascadedOption(argc, argv, "--interval", c.stop / 500);
  c.rows = (long)ceil(c.stop / c.interval - 1e-9);
  if (c.rows < 1)
    c.rows = 1;
  c.saved = benchCheckPtr(
      malloc(sizeof(double) * (size_t)(c.rows + 1) * (size_t)c.n), "malloc");
  return c;
}

/* The k-th output time (k = 1..rows), the last one exactly the stop time. */
static inline double cascadedOutputTime(const Cascaded *c, long k) {
  return k >= c->rows ? c->stop : (double)k * c->interval;
}

static inline void cascadedRecord(Cascaded *c, long k, const double *x) {
  memcpy(c->saved + (size_t)k * (size_t)c->n, x, sizeof(double) * (size_t)c->n);
}

/* f(t, x) of the ODE form, shared by the IDA residual and CVODE: the
 * model's equations divided by their coefficient tau, as ldaec's causal
 * form divides them (rounding alone moves CVODE's step count by 4% here). */
static inline void cascadedRhs(const Cascaded *c, const double *x, double *f) {
  f[0] = (1.0 - x[0]) / c->tau;
  for (long i = 1; i < c->n; ++i)
    f[i] = (x[i - 1] - x[i]) / c->tau;
}

/* The CSC pattern of df/dx and of dF/dx + cj dF/dx' (both bidiagonal):
 * column j holds row j and, but for the last column, row j + 1; `diag` and
 * `sub` are the values on and below the diagonal. */
static inline void cascadedFillCsc(const Cascaded *c, sunindextype *colptr,
                                   sunindextype *rowval, double *data,
                                   double diag, double sub) {
  sunindextype nz = 0;
  for (long j = 0; j < c->n; ++j) {
    colptr[j] = nz;
    rowval[nz] = j;
    data[nz++] = diag;
    if (j + 1 < c->n) {
      rowval[nz] = j + 1;
      data[nz++] = sub;
    }
  }
  colptr[c->n] = nz;
}

/* The CSC Jacobian (2N - 1 nonzeros) and its KLU solver. */
static inline void cascadedKlu(const Cascaded *c, N_Vector x, SUNContext ctx,
                               SUNMatrix *J, SUNLinearSolver *ls) {
  *J = benchCheckPtr(SUNSparseMatrix(c->n, c->n, 2 * c->n - 1, CSC_MAT, ctx),
                     "SUNSparseMatrix");
  *ls = benchCheckPtr(SUNLinSol_KLU(x, *J, ctx), "SUNLinSol_KLU");
}

/* One advance of the integrator to an output time, x the state after it
 * (IDASolve and CVode behind one signature). */
typedef void (*CascadedAdvance)(void *mem, double tout);

/* Records the start row and one row per output time. */
static inline void cascadedIntegrate(Cascaded *c, void *mem,
                                     CascadedAdvance advance, const double *x) {
  cascadedRecord(c, 0, x);
  for (long k = 1; k <= c->rows; ++k) {
    advance(mem, cascadedOutputTime(c, k));
    cascadedRecord(c, k, x);
  }
}

/* IDAGetNumSteps, CVodeGetNumSteps, ...: one signature for both. */
typedef int (*CascadedCounter)(void *mem, long *value);

/* The counters in the order of `ldaec --stats`: steps, residual (or
 * right-hand side) evaluations, Jacobian evaluations, error test failures,
 * nonlinear convergence failures. */
static inline void cascadedReport(Cascaded *c, double seconds, void *mem,
                                  const CascadedCounter counters[5]) {
  static const char *names[5] = {"steps", "residual evaluations",
                                 "jacobian evaluations", "error test failures",
                                 "nonlinear conv. failures"};
  benchStat("unknowns", c->n);
  for (int i = 0; i < 5; ++i) {
    long value;
    benchCheck(counters[i](mem, &value), names[i]);
    benchStat(names[i], value);
  }
  benchTime("integration time", seconds);
  printf("time,x[%ld]\n", c->n);
  for (long k = 0; k <= c->rows; ++k)
    printf("%.17g,%.17g\n", k == 0 ? 0.0 : cascadedOutputTime(c, k),
           c->saved[(size_t)k * (size_t)c->n + (size_t)c->n - 1]);
  free(c->saved);
}

#endif
