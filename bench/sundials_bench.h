/* Helpers of the hand-written SUNDIALS reference programs in bench/
 * (cascaded_ida.c, cascaded_cvode.c, robertson_ida.c): a monotonic clock,
 * return-value checks that stop the program with the failing call's name,
 * and the statistics lines they print in the layout of `ldaec --stats`
 * ("name   value"), so one parser in the bench scripts reads both.
 * Header-only: each program is one translation unit. */
#ifndef LDAE_BENCH_SUNDIALS_BENCH_H
#define LDAE_BENCH_SUNDIALS_BENCH_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static inline double benchNow(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* SUNDIALS calls return a negative flag on failure. */
static inline void benchCheck(int flag, const char *call) {
  if (flag < 0) {
    fprintf(stderr, "error: %s returned %d\n", call, flag);
    exit(3);
  }
}

static inline void *benchCheckPtr(void *p, const char *call) {
  if (!p) {
    fprintf(stderr, "error: %s returned NULL\n", call);
    exit(3);
  }
  return p;
}

static inline void benchStat(const char *name, long value) {
  fprintf(stderr, "%-28s%ld\n", name, value);
}

static inline void benchTime(const char *name, double seconds) {
  fprintf(stderr, "%-28s%.6f s\n", name, seconds);
}

#endif
