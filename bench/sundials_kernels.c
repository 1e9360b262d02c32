/* Times the serial N_Vector kernels IDA and CVODE spend their vector time
 * in, through the generic N_V* calls as the integrators make them.
 * bench/run_sundials.sh compiles this file twice, once against the -O2
 * build of scripts/build-sundials.sh and once against Debian's -O0
 * libsundials, and reports the ratio (docs/sundials.md).
 *
 * Usage: sundials_kernels N SECONDS
 * Prints one line per kernel: "name N ns-per-element", the best of
 * repeated timings filling about SECONDS per kernel. */
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

enum { NVEC = 5 };
static N_Vector v[NVEC];
static realtype coef[NVEC] = {1.0, -0.5, 0.25, -0.125, 0.0625};
/* Keeps the norms' results alive so the calls are not dropped. */
static volatile realtype sink;

static void linearSum(void) { N_VLinearSum(1.0001, v[0], -0.5, v[1], v[2]); }
static void wrmsNorm(void) { sink = N_VWrmsNorm(v[0], v[1]); }
static void prod(void) { N_VProd(v[0], v[1], v[2]); }
static void scale(void) { N_VScale(0.999, v[0], v[2]); }
static void maxNorm(void) { sink = N_VMaxNorm(v[0]); }
static void linearCombination(void) { N_VLinearCombination(NVEC - 1, coef, v, v[NVEC - 1]); }

static const struct {
  const char *name;
  void (*run)(void);
} kernels[] = {
    {"N_VLinearSum", linearSum},
    {"N_VWrmsNorm", wrmsNorm},
    {"N_VProd", prod},
    {"N_VScale", scale},
    {"N_VMaxNorm", maxNorm},
    {"N_VLinearCombination(4)", linearCombination},
};

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s N SECONDS\n", argv[0]);
    return 2;
  }
  sunindextype n = atol(argv[1]);
  double budget = atof(argv[2]);
  SUNContext ctx;
  if (SUNContext_Create(NULL, &ctx) != 0) return 1;
  for (int i = 0; i < NVEC; ++i) {
    v[i] = N_VNew_Serial(n, ctx);
    if (!v[i]) return 1;
    /* IDA and CVODE switch the fused operations on; do the same. */
    N_VEnableFusedOps_Serial(v[i], SUNTRUE);
    realtype *d = N_VGetArrayPointer(v[i]);
    for (sunindextype k = 0; k < n; ++k) d[k] = 1.0 + 1e-3 * (double)((k * (i + 3)) % 97);
  }
  for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; ++k) {
    /* Calls per timing so one timing lasts about a millisecond. */
    long calls = 1;
    double start = now();
    kernels[k].run();
    double once = now() - start;
    if (once < 1e-3) calls = (long)(1e-3 / (once > 1e-9 ? once : 1e-9)) + 1;
    double best = 1e300, spent = 0;
    while (spent < budget) {
      start = now();
      for (long c = 0; c < calls; ++c) kernels[k].run();
      double t = now() - start;
      spent += t;
      if (t < best) best = t;
    }
    printf("%s %ld %.4f\n", kernels[k].name, (long)n, 1e9 * best / (double)calls / (double)n);
  }
  for (int i = 0; i < NVEC; ++i) N_VDestroy(v[i]);
  SUNContext_Free(&ctx);
  return 0;
}
