/* CascadedFirstOrder (bench/cascaded.h) with IDA and KLU, the reference
 * bench/run_cascaded.py sets ldaec against: the residual of the ODE form
 * F = x' - f(x), its CSC Jacobian dF/dx + cj dF/dx', consistent x'(0)
 * given, IDA_NORMAL to each output time (IDA steps past it and
 * interpolates), the stop time set once at the end. The timed part is
 * everything from IDACreate to the last output row. */
#include "cascaded.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>

static int residual(realtype t, N_Vector x, N_Vector xp, N_Vector r,
                    void *data) {
  (void)t;
  const Cascaded *c = data;
  double *rr = N_VGetArrayPointer(r);
  const double *dx = N_VGetArrayPointer(xp);
  cascadedRhs(c, N_VGetArrayPointer(x), rr);
  for (long i = 0; i < c->n; ++i)
    rr[i] = dx[i] - rr[i];
  return 0;
}

static int jacobian(realtype t, realtype cj, N_Vector x, N_Vector xp,
                    N_Vector r, SUNMatrix J, void *data, N_Vector t1,
                    N_Vector t2, N_Vector t3) {
  (void)t, (void)x, (void)xp, (void)r, (void)t1, (void)t2, (void)t3;
  const Cascaded *c = data;
  double rate = 1.0 / c->tau;
  cascadedFillCsc(c, SUNSparseMatrix_IndexPointers(J),
                  SUNSparseMatrix_IndexValues(J), SUNSparseMatrix_Data(J),
                  cj + rate, -rate);
  return 0;
}

/* IDASolve's output vectors: x is the recorded state. */
static N_Vector x, xp;

static void advance(void *mem, double tout) {
  realtype reached;
  benchCheck(IDASolve(mem, tout, &reached, x, xp, IDA_NORMAL), "IDASolve");
}

int main(int argc, char **argv) {
  Cascaded c = cascadedSetup(argc, argv);
  SUNContext ctx;
  benchCheck(SUNContext_Create(NULL, &ctx), "SUNContext_Create");
  x = benchCheckPtr(N_VNew_Serial(c.n, ctx), "N_VNew_Serial");
  xp = benchCheckPtr(N_VClone(x), "N_VClone");
  N_VConst(0.0, x);
  N_VConst(0.0, xp);
  N_VGetArrayPointer(xp)[0] = 1.0 / c.tau; /* x'(0) of the first lag */

  double t0 = benchNow();
  void *mem = benchCheckPtr(IDACreate(ctx), "IDACreate");
  benchCheck(IDAInit(mem, residual, 0.0, x, xp), "IDAInit");
  benchCheck(IDASStolerances(mem, c.rtol, c.atol), "IDASStolerances");
  benchCheck(IDASetUserData(mem, &c), "IDASetUserData");
  benchCheck(IDASetStopTime(mem, c.stop), "IDASetStopTime");
  SUNMatrix J;
  SUNLinearSolver ls;
  cascadedKlu(&c, x, ctx, &J, &ls);
  benchCheck(IDASetLinearSolver(mem, ls, J), "IDASetLinearSolver");
  benchCheck(IDASetJacFn(mem, jacobian), "IDASetJacFn");

  cascadedIntegrate(&c, mem, advance, N_VGetArrayPointer(x));
  double seconds = benchNow() - t0;
  static const CascadedCounter counters[5] = {
      IDAGetNumSteps, IDAGetNumResEvals, IDAGetNumJacEvals,
      IDAGetNumErrTestFails, IDAGetNumNonlinSolvConvFails};
  cascadedReport(&c, seconds, mem, counters);

  IDAFree(&mem);
  SUNLinSolFree(ls);
  SUNMatDestroy(J);
  N_VDestroy(xp);
  N_VDestroy(x);
  SUNContext_Free(&ctx);
  return 0;
}
