// CVODE set-up and stepping for an explicit-ODE ldae_model (see
// CvodeIntegrator.h). Every SUNDIALS return value is checked; CVODE's own
// error printing is replaced by a handler that keeps the last message.
#include "CvodeIntegrator.h"
#include "SundialsSupport.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <fmt/format.h>

namespace ldae::runtime {

namespace {

using Data = Integrator::CallbackData;

/// f(t, y) = -F(t, y, 0): row i of an explicit ODE's residual is
/// y'[i] - f_i(t, y).
int evalRhs(const Data &d, double t, const double *y, double *ydot) {
  int rc = d.ev->residual(d.set, t, y, d.zeros.data(), ydot);
  if (rc == 0)
    for (int i = 0; i < d.ev->n(); ++i)
      ydot[i] = -ydot[i];
  return rc;
}

int rhsFn(sunrealtype t, N_Vector y, N_Vector ydot, void *user) {
  auto *d = static_cast<Data *>(user);
  const double *py = N_VGetArrayPointer(y);
  double *pf = N_VGetArrayPointer(ydot);
  int n = d->ev->n();
  if (!Integrator::finite(py, n)) {
    d->nonFinite = true;
    return 1;
  }
  int rc = Integrator::callbackStatus(*d, evalRhs(*d, t, py, pf), py);
  if (rc == 0 && !Integrator::finite(pf, n)) {
    d->nonFinite = true;
    return 1;
  }
  return rc;
}

/// df/dy = -dF/dy: the model's Jacobian at cj = 0, negated.
int denseJacFn(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J,
               void *user, N_Vector, N_Vector, N_Vector) {
  auto *d = static_cast<Data *>(user);
  const ldae_state_set &s = d->ev->set(d->set);
  double *a = SUNDenseMatrix_Data(J);
  int rc = s.jacobian_dense(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                            d->ev->params(), 0.0, a);
  long n = long(d->ev->n());
  for (long k = 0; k < n * n; ++k)
    a[k] = -a[k];
  return rc > 0 ? 1 : (rc < 0 ? -1 : 0);
}

int sparseJacFn(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J,
                void *user, N_Vector, N_Vector, N_Vector) {
  auto *d = static_cast<Data *>(user);
  const ldae_state_set &s = d->ev->set(d->set);
  int n = d->ev->n();
  sundials::copyPattern(J, s, n);
  double *a = SUNSparseMatrix_Data(J);
  int rc = s.jacobian_csc(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                          d->ev->params(), 0.0, a);
  for (int q = 0; q < s.jac_nnz; ++q)
    a[q] = -a[q];
  return rc > 0 ? 1 : (rc < 0 ? -1 : 0);
}

int rootFn(sunrealtype t, N_Vector y, sunrealtype *g, void *user) {
  auto *d = static_cast<Data *>(user);
  const double *py = N_VGetArrayPointer(y);
  if (evalRhs(*d, t, py, d->work.data()) != 0)
    return -1;
  const ldae_model &m = d->ev->model();
  return m.roots(t, py, d->work.data(), d->ev->params(), g) == 0 ? 0 : -1;
}

/// CVODE's failure returns in the failure report's terms.
StepStatus failure(int flag) {
  switch (flag) {
  case CV_TOO_MUCH_WORK:
    return StepStatus::failed(FailureKind::TooMuchWork, "CV_TOO_MUCH_WORK");
  case CV_TOO_MUCH_ACC:
    return StepStatus::failed(FailureKind::TooMuchAccuracy, "CV_TOO_MUCH_ACC");
  case CV_ERR_FAILURE:
    return StepStatus::failed(FailureKind::ErrorTest, "CV_ERR_FAILURE");
  case CV_CONV_FAILURE:
    return StepStatus::failed(FailureKind::Convergence, "CV_CONV_FAILURE");
  case CV_LSETUP_FAIL:
    return StepStatus::failed(FailureKind::LinearSetup, "CV_LSETUP_FAIL");
  case CV_LSOLVE_FAIL:
    return StepStatus::failed(FailureKind::LinearSolve, "CV_LSOLVE_FAIL");
  case CV_RHSFUNC_FAIL:
    return StepStatus::failed(FailureKind::Domain, "CV_RHSFUNC_FAIL");
  case CV_REPTD_RHSFUNC_ERR:
    return StepStatus::failed(FailureKind::Domain, "CV_REPTD_RHSFUNC_ERR");
  case CV_UNREC_RHSFUNC_ERR:
    return StepStatus::failed(FailureKind::Domain, "CV_UNREC_RHSFUNC_ERR");
  case CV_FIRST_RHSFUNC_ERR:
    return StepStatus::failed(FailureKind::NoStart, "CV_FIRST_RHSFUNC_ERR");
  case CV_RTFUNC_FAIL:
    return StepStatus::failed(FailureKind::RootFunction, "CV_RTFUNC_FAIL");
  default:
    return StepStatus::failed(FailureKind::Other,
                              fmt::format("CVODE flag {}", flag));
  }
}

} // namespace

struct CvodeIntegrator::Impl {
  SUNContext ctx = nullptr;
  void *mem = nullptr;
  N_Vector y = nullptr, atol = nullptr, tmp = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  SUNNonlinearSolver NLS = nullptr;
  double tstop = 0;
  int rootCount = 0;
  /// y' = f(t, y) at the current point, computed when first asked for.
  mutable std::vector<double> yp;
  mutable bool ypValid = false;
  double t = 0;

  ~Impl() {
    if (mem)
      CVodeFree(&mem);
    if (NLS)
      SUNNonlinSolFree(NLS);
    if (LS)
      SUNLinSolFree(LS);
    if (A)
      SUNMatDestroy(A);
    for (N_Vector v : {y, atol, tmp})
      if (v)
        N_VDestroy(v);
    if (ctx)
      SUNContext_Free(&ctx);
  }
};

CvodeIntegrator::CvodeIntegrator(const ModelEval &ev, bool adams)
    : Integrator(ev), impl_(std::make_unique<Impl>()), adams_(adams) {
  shared_.ev = &ev;
  shared_.zeros.assign(ev.n(), 0.0);
  shared_.work.assign(ev.n(), 0.0);
  impl_->yp.assign(ev.n(), 0.0);
}

CvodeIntegrator::~CvodeIntegrator() = default;

Expected<bool> CvodeIntegrator::init(int set, double t0, const double *y,
                                     const double *, double rtol,
                                     const std::vector<double> &atol,
                                     double tstop, bool) {
  Impl &I = *impl_;
  int n = ev_.n();
  shared_.set = set;
  LDAE_SUNDIALS_CHECK(SUNContext_Create(nullptr, &I.ctx));
  I.y = N_VNew_Serial(n, I.ctx);
  I.atol = N_VNew_Serial(n, I.ctx);
  I.tmp = N_VNew_Serial(n, I.ctx);
  if (!I.y || !I.atol || !I.tmp)
    return Error{"internal error: cannot allocate CVODE vectors"};
  std::copy(y, y + n, N_VGetArrayPointer(I.y));
  std::copy(atol.begin(), atol.end(), N_VGetArrayPointer(I.atol));
  I.t = t0;
  I.ypValid = false;
  I.mem = CVodeCreate(adams_ ? CV_ADAMS : CV_BDF, I.ctx);
  if (!I.mem)
    return Error{"internal error: CVodeCreate failed"};
  LDAE_SUNDIALS_CHECK(CVodeSetErrHandlerFn(I.mem, sundials::keepMessage, &shared_));
  LDAE_SUNDIALS_CHECK(CVodeInit(I.mem, rhsFn, t0, I.y));
  LDAE_SUNDIALS_CHECK(CVodeSetUserData(I.mem, &shared_));
  LDAE_SUNDIALS_CHECK(CVodeSVtolerances(I.mem, rtol, I.atol));
  I.tstop = tstop;
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(I.mem, tstop));
  const ldae_model &m = ev_.model();
  if (m.n_roots > 0 && m.roots)
    LDAE_SUNDIALS_CHECK(CVodeRootInit(I.mem, m.n_roots, rootFn));
  return setupSolver();
}

Expected<bool> CvodeIntegrator::setupSolver() {
  Impl &I = *impl_;
  if (adams_) {
    // Non-stiff: fixed-point iteration needs no Jacobian or linear solve.
    I.NLS = SUNNonlinSol_FixedPoint(I.y, 0, I.ctx);
    if (!I.NLS)
      return Error{"internal error: cannot create the fixed-point solver"};
    LDAE_SUNDIALS_CHECK(CVodeSetNonlinearSolver(I.mem, I.NLS));
    return true;
  }
  const ldae_state_set &s = ev_.set(shared_.set);
  int n = ev_.n();
  bool sparse = n > LDAE_DENSE_THRESHOLD && s.jacobian_csc && s.jac_colptr;
  I.A = sparse ? SUNSparseMatrix(n, n, std::max(s.jac_nnz, 1), CSC_MAT, I.ctx)
               : SUNDenseMatrix(n, n, I.ctx);
  if (!I.A)
    return Error{"internal error: cannot create the Jacobian matrix"};
  I.LS = sparse ? SUNLinSol_KLU(I.y, I.A, I.ctx)
                : SUNLinSol_Dense(I.y, I.A, I.ctx);
  if (!I.LS)
    return Error{"internal error: cannot create the linear solver"};
  LDAE_SUNDIALS_CHECK(CVodeSetLinearSolver(I.mem, I.LS, I.A));
  sparse_ = sparse;
  if (sparse)
    LDAE_SUNDIALS_CHECK(CVodeSetJacFn(I.mem, sparseJacFn));
  else
    LDAE_SUNDIALS_CHECK(CVodeSetJacFn(I.mem, s.jacobian_dense ? denseJacFn : nullptr));
  return true;
}

Expected<bool> CvodeIntegrator::reinit(int set, double t, const double *y,
                                       const double *) {
  Impl &I = *impl_;
  if (set != shared_.set)
    return Error{"internal error: CVODE runs a model with one state set"};
  SimStats now;
  addCounters(now);
  saved_ = now; // CVodeReInit zeroes CVODE's counters
  I.rootCount = 0;
  std::copy(y, y + ev_.n(), N_VGetArrayPointer(I.y));
  I.t = t;
  I.ypValid = false;
  LDAE_SUNDIALS_CHECK(CVodeReInit(I.mem, t, I.y));
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(I.mem, I.tstop));
  return true;
}

StepStatus CvodeIntegrator::completeStart(double) {
  Impl &I = *impl_;
  int rc = evalRhs(shared_, I.t, N_VGetArrayPointer(I.y), I.yp.data());
  if (rc != 0) {
    callbackStatus(shared_, rc, N_VGetArrayPointer(I.y));
    return StepStatus::failed(rc > 0 ? FailureKind::Domain
                                     : FailureKind::NoStart,
                              "CV_FIRST_RHSFUNC_ERR");
  }
  I.ypValid = true;
  return {};
}

Expected<bool> CvodeIntegrator::setStopTime(double tstop) {
  impl_->tstop = tstop;
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(impl_->mem, tstop));
  return true;
}

StepStatus CvodeIntegrator::step(double &tret) {
  Impl &I = *impl_;
  shared_.nonFinite = false;
  int flag = CVode(I.mem, I.tstop, I.y, &tret, CV_ONE_STEP);
  I.ypValid = false;
  if (flag < 0) {
    return overflowAware(failure(flag));
  }
  I.t = tret;
  if (flag == CV_ROOT_RETURN) {
    ++I.rootCount;
    return {StepStatus::Root};
  }
  return {flag == CV_TSTOP_RETURN ? StepStatus::StopReached
                                  : StepStatus::Step};
}

Expected<bool> CvodeIntegrator::interpolate(double t, double *y, double *yp) {
  Impl &I = *impl_;
  LDAE_SUNDIALS_CHECK(CVodeGetDky(I.mem, t, 0, I.tmp));
  const double *src = N_VGetArrayPointer(I.tmp);
  std::copy(src, src + ev_.n(), y);
  // The derivative from f at the interpolated point, not the polynomial's:
  // outputs that read y' then satisfy the equations.
  if (evalRhs(shared_, t, y, yp) != 0)
    return Error{fmt::format("the right-hand side cannot be evaluated at the "
                             "output time {:.10g}",
                             t)};
  return true;
}

const double *CvodeIntegrator::y() const {
  return N_VGetArrayPointer(impl_->y);
}

const double *CvodeIntegrator::yp() const {
  Impl &I = *impl_;
  if (!I.ypValid) {
    if (evalRhs(shared_, I.t, N_VGetArrayPointer(I.y), I.yp.data()) != 0)
      std::fill(I.yp.begin(), I.yp.end(), 0.0);
    I.ypValid = true;
  }
  return I.yp.data();
}

void CvodeIntegrator::addCounters(SimStats &st) const {
  void *mem = impl_->mem;
  if (mem == nullptr)
    return;
  long nst = 0, nfe = 0, nfeLS = 0, nje = 0, netf = 0, ncfn = 0;
  // Getters only fail on a null memory block (checked above) or, for the
  // linear solver's, without one (Adams): those stay 0.
  CVodeGetNumSteps(mem, &nst);
  CVodeGetNumRhsEvals(mem, &nfe);
  CVodeGetNumErrTestFails(mem, &netf);
  CVodeGetNumNonlinSolvConvFails(mem, &ncfn);
  if (!adams_) {
    CVodeGetNumLinRhsEvals(mem, &nfeLS);
    CVodeGetNumJacEvals(mem, &nje);
  }
  st.steps += nst + saved_.steps;
  st.residualEvals += nfe + nfeLS + saved_.residualEvals;
  st.jacobianEvals += nje + saved_.jacobianEvals;
  st.errorTestFailures += netf + saved_.errorTestFailures;
  st.convergenceFailures += ncfn + saved_.convergenceFailures;
  st.rootsFound += impl_->rootCount + saved_.rootsFound;
}

std::vector<int> CvodeIntegrator::rootsFound() const {
  return sundials::rootInfo(ev_.model().n_roots, [&](int *found) {
    return CVodeGetRootInfo(impl_->mem, found);
  });
}

std::vector<double> CvodeIntegrator::weightedErrors() const {
  void *mem = impl_->mem;
  return sundials::weightedErrors(
      impl_->y, ev_.n(), [&](N_Vector w) { return CVodeGetErrWeights(mem, w); },
      [&](N_Vector e) { return CVodeGetEstLocalErrors(mem, e); });
}

double CvodeIntegrator::currentTime() const {
  return sundials::valueOrZero(
      [&](double *v) { return CVodeGetCurrentTime(impl_->mem, v); });
}

double CvodeIntegrator::lastStep() const {
  return sundials::valueOrZero(
      [&](double *v) { return CVodeGetLastStep(impl_->mem, v); });
}

double CvodeIntegrator::iterationCj() const {
  // CVODE's Newton matrix is I - gamma df/dy = gamma (dF/dy + (1/gamma) I).
  double gamma = 0;
  if (CVodeGetCurrentGamma(impl_->mem, &gamma) < 0 || gamma == 0)
    return 0;
  return 1.0 / gamma;
}

} // namespace ldae::runtime
