/* CascadedFirstOrder (bench/cascaded.h) with CVODE, BDF and KLU: the
 * right-hand side f(x), its CSC Jacobian df/dx, CV_NORMAL to each output
 * time (CVODE steps past it and interpolates), the stop time set once at
 * the end. The timed part is everything from CVodeCreate to the last
 * output row. */
#include "cascaded.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>

static int rhs(realtype t, N_Vector x, N_Vector f, void *data) {
  (void)t;
  cascadedRhs(data, N_VGetArrayPointer(x), N_VGetArrayPointer(f));
  return 0;
}

static int jacobian(realtype t, N_Vector x, N_Vector f, SUNMatrix J, void *data,
                    N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t, (void)x, (void)f, (void)t1, (void)t2, (void)t3;
  const Cascaded *c = data;
  double rate = 1.0 / c->tau;
  cascadedFillCsc(c, SUNSparseMatrix_IndexPointers(J),
                  SUNSparseMatrix_IndexValues(J), SUNSparseMatrix_Data(J),
                  -rate, rate);
  return 0;
}

/* CVode's output vector, the recorded state. */
static N_Vector x;

static void advance(void *mem, double tout) {
  realtype reached;
  benchCheck(CVode(mem, tout, x, &reached, CV_NORMAL), "CVode");
}

int main(int argc, char **argv) {
  Cascaded c = cascadedSetup(argc, argv);
  SUNContext ctx;
  benchCheck(SUNContext_Create(NULL, &ctx), "SUNContext_Create");
  x = benchCheckPtr(N_VNew_Serial(c.n, ctx), "N_VNew_Serial");
  N_VConst(0.0, x);

  double t0 = benchNow();
  void *mem = benchCheckPtr(CVodeCreate(CV_BDF, ctx), "CVodeCreate");
  benchCheck(CVodeInit(mem, rhs, 0.0, x), "CVodeInit");
  benchCheck(CVodeSStolerances(mem, c.rtol, c.atol), "CVodeSStolerances");
  benchCheck(CVodeSetUserData(mem, &c), "CVodeSetUserData");
  benchCheck(CVodeSetStopTime(mem, c.stop), "CVodeSetStopTime");
  SUNMatrix J;
  SUNLinearSolver ls;
  cascadedKlu(&c, x, ctx, &J, &ls);
  benchCheck(CVodeSetLinearSolver(mem, ls, J), "CVodeSetLinearSolver");
  benchCheck(CVodeSetJacFn(mem, jacobian), "CVodeSetJacFn");

  cascadedIntegrate(&c, mem, advance, N_VGetArrayPointer(x));
  double seconds = benchNow() - t0;
  static const CascadedCounter counters[5] = {
      CVodeGetNumSteps, CVodeGetNumRhsEvals, CVodeGetNumJacEvals,
      CVodeGetNumErrTestFails, CVodeGetNumNonlinSolvConvFails};
  cascadedReport(&c, seconds, mem, counters);

  CVodeFree(&mem);
  SUNLinSolFree(ls);
  SUNMatDestroy(J);
  N_VDestroy(x);
  SUNContext_Free(&ctx);
  return 0;
}
