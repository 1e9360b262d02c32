/* Robertson's kinetics as SUNDIALS' idaRoberts_dns example poses it, the
 * reference of bench/run_robertson.py's whole-process time: the index-1
 * DAE
 *
 *   y1' = -k1 y1 + k2 y2 y3
 *   y2' =  k1 y1 - k2 y2 y3 - k3 y2^2
 *   0   =  y1 + y2 + y3 - 1,      k = (0.04, 1e4, 3e7),
 *
 * y(0) = (1, 0, 0) with the consistent y'(0) = (-0.04, 0.04, 0), rtol 1e-4,
 * atol (1e-8, 1e-6, 1e-6), every unknown error-tested (no id vector),
 * dense LU with the analytic Jacobian dF/dy + cj dF/dy', IDA_NORMAL to the
 * output times 0.4, 4, ..., 4e10. Unlike the example it finds no roots
 * (the lsd model has no events). Writes the CSV ldaec writes (time, y1,
 * y2, y3 with the start row) to the file given with -o, else stdout.
 *
 * Usage: robertson_ida [-o FILE] */
#include "sundials_bench.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <string.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

enum { kUnknowns = 3, kOutputs = 12 };
static const double k1 = 0.04, k2 = 1e4, k3 = 3e7;

static int residual(realtype t, N_Vector yy, N_Vector yyp, N_Vector r,
                    void *data) {
  (void)t, (void)data;
  const double *y = N_VGetArrayPointer(yy), *yp = N_VGetArrayPointer(yyp);
  double *f = N_VGetArrayPointer(r);
  f[0] = -k1 * y[0] + k2 * y[1] * y[2] - yp[0];
  f[1] = k1 * y[0] - k2 * y[1] * y[2] - k3 * y[1] * y[1] - yp[1];
  f[2] = y[0] + y[1] + y[2] - 1.0;
  return 0;
}

static int jacobian(realtype t, realtype cj, N_Vector yy, N_Vector yyp,
                    N_Vector r, SUNMatrix J, void *data, N_Vector t1,
                    N_Vector t2, N_Vector t3) {
  (void)t, (void)yyp, (void)r, (void)data, (void)t1, (void)t2, (void)t3;
  const double *y = N_VGetArrayPointer(yy);
  SM_ELEMENT_D(J, 0, 0) = -k1 - cj;
  SM_ELEMENT_D(J, 0, 1) = k2 * y[2];
  SM_ELEMENT_D(J, 0, 2) = k2 * y[1];
  SM_ELEMENT_D(J, 1, 0) = k1;
  SM_ELEMENT_D(J, 1, 1) = -k2 * y[2] - 2 * k3 * y[1] - cj;
  SM_ELEMENT_D(J, 1, 2) = -k2 * y[1];
  SM_ELEMENT_D(J, 2, 0) = 1.0;
  SM_ELEMENT_D(J, 2, 1) = 1.0;
  SM_ELEMENT_D(J, 2, 2) = 1.0;
  return 0;
}

static void writeRow(FILE *out, double t, N_Vector yy) {
  const double *y = N_VGetArrayPointer(yy);
  fprintf(out, "%.17g,%.17g,%.17g,%.17g\n", t, y[0], y[1], y[2]);
}

int main(int argc, char **argv) {
  FILE *out = stdout;
  if (argc == 3 && strcmp(argv[1], "-o") == 0)
    out = benchCheckPtr(fopen(argv[2], "w"), "fopen");
  else if (argc != 1) {
    fprintf(stderr, "usage: %s [-o FILE]\n", argv[0]);
    return 2;
  }
  SUNContext ctx;
  benchCheck(SUNContext_Create(NULL, &ctx), "SUNContext_Create");
  N_Vector yy = benchCheckPtr(N_VNew_Serial(kUnknowns, ctx), "N_VNew_Serial");
  N_Vector yp = benchCheckPtr(N_VClone(yy), "N_VClone");
  N_Vector atol = benchCheckPtr(N_VClone(yy), "N_VClone");
  double *y0 = N_VGetArrayPointer(yy), *yp0 = N_VGetArrayPointer(yp),
         *a = N_VGetArrayPointer(atol);
  y0[0] = 1.0, y0[1] = 0.0, y0[2] = 0.0;
  yp0[0] = -k1, yp0[1] = k1, yp0[2] = 0.0;
  a[0] = 1e-8, a[1] = 1e-6, a[2] = 1e-6;

  void *mem = benchCheckPtr(IDACreate(ctx), "IDACreate");
  benchCheck(IDAInit(mem, residual, 0.0, yy, yp), "IDAInit");
  benchCheck(IDASVtolerances(mem, 1e-4, atol), "IDASVtolerances");
  SUNMatrix J = benchCheckPtr(SUNDenseMatrix(kUnknowns, kUnknowns, ctx),
                              "SUNDenseMatrix");
  SUNLinearSolver ls =
      benchCheckPtr(SUNLinSol_Dense(yy, J, ctx), "SUNLinSol_Dense");
  benchCheck(IDASetLinearSolver(mem, ls, J), "IDASetLinearSolver");
  benchCheck(IDASetJacFn(mem, jacobian), "IDASetJacFn");

  fprintf(out, "time,y1,y2,y3\n");
  writeRow(out, 0.0, yy);
  double tout = 0.4;
  for (int k = 0; k < kOutputs; ++k, tout *= 10) {
    realtype reached;
    benchCheck(IDASolve(mem, tout, &reached, yy, yp, IDA_NORMAL), "IDASolve");
    writeRow(out, reached, yy);
  }
  long steps;
  benchCheck(IDAGetNumSteps(mem, &steps), "IDAGetNumSteps");
  benchStat("steps", steps);
  if (out != stdout)
    fclose(out);

  IDAFree(&mem);
  SUNLinSolFree(ls);
  SUNMatDestroy(J);
  N_VDestroy(atol);
  N_VDestroy(yp);
  N_VDestroy(yy);
  SUNContext_Free(&ctx);
  return 0;
}
