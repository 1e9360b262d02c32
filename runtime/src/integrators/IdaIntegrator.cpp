// IDA set-up and stepping for an ldae_model (see IdaIntegrator.h). Every
// SUNDIALS return value is checked; IDA's own error printing is replaced by
// a handler that keeps the last message for our failure report.
#include "integrators/IdaIntegrator.h"
#include "integrators/SundialsSupport.h"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <fmt/format.h>

namespace ldae::runtime {

namespace {

using Data = Integrator::CallbackData;

int residualFn(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void *user) {
  auto *d = static_cast<Data *>(user);
  int n = d->ev->n();
  const double *py = N_VGetArrayPointer(y), *pyp = N_VGetArrayPointer(yp);
  double *pr = N_VGetArrayPointer(r);
  if (!Integrator::finite(py, n) || !Integrator::finite(pyp, n)) {
    d->nonFinite = true;
    return 1;
  }
  int rc = Integrator::callbackStatus(
      *d, d->ev->residual(d->set, t, py, pyp, pr), py);
  if (rc == 0 && !Integrator::finite(pr, n)) {
    d->nonFinite = true;
    return 1;
  }
  return rc;
}

int denseJacFn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp,
               N_Vector r, SUNMatrix J, void *user, N_Vector, N_Vector,
               N_Vector) {
  auto *d = static_cast<Data *>(user);
  const ldae_state_set &s = d->ev->set(d->set);
  // SUNDenseMatrix stores columns contiguously: exactly the ABI's layout.
  int rc = s.jacobian_dense(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                            d->ev->params(), cj, SUNDenseMatrix_Data(J));
  return rc > 0 ? 1 : (rc < 0 ? -1 : 0);
}

int sparseJacFn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp,
                N_Vector r, SUNMatrix J, void *user, N_Vector, N_Vector,
                N_Vector) {
  auto *d = static_cast<Data *>(user);
  const ldae_state_set &s = d->ev->set(d->set);
  int n = d->ev->n();
  sundials::copyPattern(J, s, n);
  int rc = s.jacobian_csc(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                          d->ev->params(), cj, SUNSparseMatrix_Data(J));
  return rc > 0 ? 1 : (rc < 0 ? -1 : 0);
}

int rootFn(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype *g, void *user) {
  auto *d = static_cast<Data *>(user);
  const ldae_model &m = d->ev->model();
  int rc = m.roots(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                   d->ev->params(), g);
  return rc == 0 ? 0 : -1;
}

/// IDAEwtFn: the error weights at the step's starting point.
int ewtFn(N_Vector y, N_Vector ewt, void *user) {
  auto *d = static_cast<Data *>(user);
  d->weights->compute(d->t, N_VGetArrayPointer(y), d->yp,
                      N_VGetArrayPointer(ewt));
  return 0;
}

/// IDA's failure returns in the failure report's terms.
StepStatus failure(int flag) {
  switch (flag) {
  case IDA_TOO_MUCH_WORK:
    return StepStatus::failed(FailureKind::TooMuchWork, "IDA_TOO_MUCH_WORK");
  case IDA_TOO_MUCH_ACC:
    return StepStatus::failed(FailureKind::TooMuchAccuracy, "IDA_TOO_MUCH_ACC");
  case IDA_ERR_FAIL:
    return StepStatus::failed(FailureKind::ErrorTest, "IDA_ERR_FAIL");
  case IDA_CONV_FAIL:
    return StepStatus::failed(FailureKind::Convergence, "IDA_CONV_FAIL");
  case IDA_LSETUP_FAIL:
    return StepStatus::failed(FailureKind::LinearSetup, "IDA_LSETUP_FAIL");
  case IDA_LSOLVE_FAIL:
    return StepStatus::failed(FailureKind::LinearSolve, "IDA_LSOLVE_FAIL");
  case IDA_RES_FAIL:
    return StepStatus::failed(FailureKind::Domain, "IDA_RES_FAIL");
  case IDA_REP_RES_ERR:
    return StepStatus::failed(FailureKind::Domain, "IDA_REP_RES_ERR");
  case IDA_RTFUNC_FAIL:
    return StepStatus::failed(FailureKind::RootFunction, "IDA_RTFUNC_FAIL");
  case IDA_NO_RECOVERY:
    return StepStatus::failed(FailureKind::NoStart, "IDA_NO_RECOVERY");
  case IDA_LINESEARCH_FAIL:
    return StepStatus::failed(FailureKind::NoStart, "IDA_LINESEARCH_FAIL");
  case IDA_FIRST_RES_FAIL:
    return StepStatus::failed(FailureKind::NoStart, "IDA_FIRST_RES_FAIL");
  default:
    return StepStatus::failed(FailureKind::Other,
                              fmt::format("IDA flag {}", flag));
  }
}

} // namespace

struct IdaIntegrator::Impl {
  SUNContext ctx = nullptr;
  void *mem = nullptr;
  N_Vector y = nullptr, yp = nullptr, id = nullptr, atol = nullptr,
           tmp = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  double tstop = 0;
  int rootCount = 0;
  bool rootReturned = false; // the last step returned a root, no restart since

  void freeSolver() {
    if (LS)
      SUNLinSolFree(LS);
    if (A)
      SUNMatDestroy(A);
    LS = nullptr;
    A = nullptr;
  }
  ~Impl() {
    if (mem)
      IDAFree(&mem);
    freeSolver();
    for (N_Vector v : {y, yp, id, atol, tmp})
      if (v)
        N_VDestroy(v);
    if (ctx)
      SUNContext_Free(&ctx);
  }
};

IdaIntegrator::IdaIntegrator(const ModelEval &ev)
    : Integrator(ev), impl_(std::make_unique<Impl>()) {
  shared_.ev = &ev;
}

IdaIntegrator::~IdaIntegrator() = default;

Expected<bool> IdaIntegrator::init(int set, double t0, const double *y,
                                   const double *yp, double rtol,
                                   const std::vector<double> &atol,
                                   double tstop, bool errorTestAlgebraic) {
  Impl &I = *impl_;
  int n = ev_.n();
  shared_.set = set;
  LDAE_SUNDIALS_CHECK(SUNContext_Create(nullptr, &I.ctx));
  I.y = N_VNew_Serial(n, I.ctx);
  I.yp = N_VNew_Serial(n, I.ctx);
  I.id = N_VNew_Serial(n, I.ctx);
  I.atol = N_VNew_Serial(n, I.ctx);
  I.tmp = N_VNew_Serial(n, I.ctx);
  if (!I.y || !I.yp || !I.id || !I.atol || !I.tmp)
    return Error{"internal error: cannot allocate IDA vectors"};
  std::copy(y, y + n, N_VGetArrayPointer(I.y));
  std::copy(yp, yp + n, N_VGetArrayPointer(I.yp));
  std::copy(atol.begin(), atol.end(), N_VGetArrayPointer(I.atol));
  I.mem = IDACreate(I.ctx);
  if (!I.mem)
    return Error{"internal error: IDACreate failed"};
  LDAE_SUNDIALS_CHECK(
      IDASetErrHandlerFn(I.mem, sundials::keepMessage, &shared_));
  LDAE_SUNDIALS_CHECK(IDAInit(I.mem, residualFn, t0, I.y, I.yp));
  LDAE_SUNDIALS_CHECK(IDASetUserData(I.mem, &shared_));
  shared_.t = t0;
  shared_.yp = N_VGetArrayPointer(I.yp);
  if (shared_.weights)
    LDAE_SUNDIALS_CHECK(IDAWFtolerances(I.mem, ewtFn));
  else
    LDAE_SUNDIALS_CHECK(IDASVtolerances(I.mem, rtol, I.atol));
  I.tstop = tstop;
  LDAE_SUNDIALS_CHECK(IDASetStopTime(I.mem, tstop));
  const ldae_model &m = ev_.model();
  if (m.n_roots > 0 && m.roots)
    LDAE_SUNDIALS_CHECK(IDARootInit(I.mem, m.n_roots, rootFn));
  auto ok = setupId();
  if (!ok)
    return ok;
  // Which unknowns the error test may leave out is the run's decision
  // (docs/runtime.md, "The error test").
  LDAE_SUNDIALS_CHECK(
      IDASetSuppressAlg(I.mem, errorTestAlgebraic ? SUNFALSE : SUNTRUE));
  return setupLinearSolver();
}

Expected<bool> IdaIntegrator::setupId() {
  const ldae_state_set &s = ev_.set(shared_.set);
  double *id = N_VGetArrayPointer(impl_->id);
  for (int i = 0; i < ev_.n(); ++i)
    id[i] = s.is_differential[i] ? 1.0 : 0.0;
  LDAE_SUNDIALS_CHECK(IDASetId(impl_->mem, impl_->id));
  return true;
}

Expected<bool> IdaIntegrator::setupLinearSolver() {
  Impl &I = *impl_;
  const ldae_state_set &s = ev_.set(shared_.set);
  int n = ev_.n();
  bool sparse = n > LDAE_DENSE_THRESHOLD && s.jacobian_csc && s.jac_colptr;
  if (I.LS && !sparse && !sparse_) {
    // Dense to dense: the matrix and solver stay; only the Jacobian source
    // changes (IDA's difference quotients when the set has none).
    LDAE_SUNDIALS_CHECK(
        IDASetJacFn(I.mem, s.jacobian_dense ? denseJacFn : nullptr));
    return true;
  }
  // A new matrix (the sparse pattern may differ between sets): build the
  // new solver first, hand it to IDA, then free the old one.
  SUNMatrix A =
      sparse ? SUNSparseMatrix(n, n, std::max(s.jac_nnz, 1), CSC_MAT, I.ctx)
             : SUNDenseMatrix(n, n, I.ctx);
  if (!A)
    return Error{"internal error: cannot create the Jacobian matrix"};
  SUNLinearSolver LS =
      sparse ? SUNLinSol_KLU(I.y, A, I.ctx) : SUNLinSol_Dense(I.y, A, I.ctx);
  if (!LS) {
    SUNMatDestroy(A);
    return Error{"internal error: cannot create the linear solver"};
  }
  int flag = IDASetLinearSolver(I.mem, LS, A);
  if (flag < 0) {
    SUNLinSolFree(LS);
    SUNMatDestroy(A);
    return sundials::callError("IDASetLinearSolver", flag);
  }
  I.freeSolver();
  I.A = A;
  I.LS = LS;
  sparse_ = sparse;
  if (sparse)
    LDAE_SUNDIALS_CHECK(IDASetJacFn(I.mem, sparseJacFn));
  else
    LDAE_SUNDIALS_CHECK(
        IDASetJacFn(I.mem, s.jacobian_dense ? denseJacFn : nullptr));
  return true;
}

void IdaIntegrator::addCounters(SimStats &st) const {
  void *mem = impl_->mem;
  if (mem == nullptr)
    return;
  long nst = 0, nre = 0, nreLS = 0, nje = 0, netf = 0, ncfn = 0;
  // Getters only fail on a null memory block, checked above.
  IDAGetNumSteps(mem, &nst);
  IDAGetNumResEvals(mem, &nre);
  IDAGetNumLinResEvals(mem, &nreLS);
  IDAGetNumJacEvals(mem, &nje);
  IDAGetNumErrTestFails(mem, &netf);
  IDAGetNumNonlinSolvConvFails(mem, &ncfn);
  st.steps += nst + saved_.steps;
  st.residualEvals += nre + nreLS + saved_.residualEvals;
  st.jacobianEvals += nje + saved_.jacobianEvals;
  st.errorTestFailures += netf + saved_.errorTestFailures;
  st.convergenceFailures += ncfn + saved_.convergenceFailures;
  st.rootsFound += impl_->rootCount + saved_.rootsFound;
}

Expected<bool> IdaIntegrator::reinit(int set, double t, const double *y,
                                     const double *yp) {
  Impl &I = *impl_;
  SimStats now;
  addCounters(now);
  saved_ = now; // IDAReInit zeroes IDA's counters
  I.rootCount = 0;
  I.rootReturned = false;
  int n = ev_.n();
  std::copy(y, y + n, N_VGetArrayPointer(I.y));
  std::copy(yp, yp + n, N_VGetArrayPointer(I.yp));
  int oldSet = shared_.set;
  shared_.set = set;
  shared_.t = t;
  LDAE_SUNDIALS_CHECK(IDAReInit(I.mem, t, I.y, I.yp));
  LDAE_SUNDIALS_CHECK(IDASetStopTime(I.mem, I.tstop));
  auto ok = setupId();
  if (!ok)
    return ok;
  if (oldSet != set)
    return setupLinearSolver();
  return true;
}

StepStatus IdaIntegrator::completeStart(double tout1) {
  Impl &I = *impl_;
  int flag = IDACalcIC(I.mem, IDA_YA_YDP_INIT, tout1);
  if (flag >= 0)
    flag = IDAGetConsistentIC(I.mem, I.y, I.yp);
  return flag < 0 ? failure(flag) : StepStatus{};
}

Expected<bool> IdaIntegrator::setStopTime(double tstop) {
  impl_->tstop = tstop;
  LDAE_SUNDIALS_CHECK(IDASetStopTime(impl_->mem, tstop));
  return true;
}

Expected<bool> IdaIntegrator::setMaxStep(double hmax) {
  LDAE_SUNDIALS_CHECK(IDASetMaxStep(impl_->mem, hmax));
  return true;
}

StepStatus IdaIntegrator::step(double &tret) {
  Impl &I = *impl_;
  shared_.nonFinite = false;
  const double from = shared_.t;
  int flag = IDASolve(I.mem, oneStepTarget(from, I.tstop), &tret, I.y, I.yp,
                      IDA_ONE_STEP);
  if (flag == IDA_ILL_INPUT && I.rootReturned &&
      shared_.message.find("IDARcheck2") != std::string::npos) {
    // Going on from the root it returned, IDA found a root function it
    // watches exactly zero there and just past it ("Root found at and very
    // near t": a diode's v = vs - vc, two equal doubles, leaving zero
    // tangentially). Restarted at the root, IDA sets that function aside
    // until it leaves zero. Only then: a restart at every root return
    // where some root function was zero restarted for functions IDA had
    // set aside already (a free clutch's normal force in `fn <= 0`, zero
    // for seconds), each first step a thousandth of the way to the next
    // stop, and MSL's SimpleGearShift, whose locked brake's speed crosses
    // zero by round-off at nearly every step, collapsed its step size.
    const std::vector<double> y(N_VGetArrayPointer(I.y),
                                N_VGetArrayPointer(I.y) + ev_.n()),
        yp(N_VGetArrayPointer(I.yp), N_VGetArrayPointer(I.yp) + ev_.n());
    if (auto re = reinit(shared_.set, from, y.data(), yp.data()); !re)
      return StepStatus::failed(FailureKind::Other, re.error());
    flag = IDASolve(I.mem, oneStepTarget(from, I.tstop), &tret, I.y, I.yp,
                    IDA_ONE_STEP);
  }
  I.rootReturned = flag == IDA_ROOT_RETURN;
  shared_.t = tret;
  if (flag < 0) {
    return overflowAware(failure(flag));
  }
  if (flag == IDA_ROOT_RETURN) {
    ++I.rootCount;
    return {StepStatus::Root};
  }
  return {flag == IDA_TSTOP_RETURN ? StepStatus::StopReached
                                   : StepStatus::Step};
}

Expected<bool> IdaIntegrator::interpolate(double t, double *y, double *yp) {
  Impl &I = *impl_;
  int n = ev_.n();
  for (auto [k, out] : {std::pair{0, y}, {1, yp}}) {
    LDAE_SUNDIALS_CHECK(IDAGetDky(I.mem, t, k, I.tmp));
    const double *src = N_VGetArrayPointer(I.tmp);
    std::copy(src, src + n, out);
  }
  return true;
}

const double *IdaIntegrator::y() const { return N_VGetArrayPointer(impl_->y); }
const double *IdaIntegrator::yp() const {
  return N_VGetArrayPointer(impl_->yp);
}

std::vector<int> IdaIntegrator::rootsFound() const {
  return sundials::rootInfo(ev_.model().n_roots, [&](int *found) {
    return IDAGetRootInfo(impl_->mem, found);
  });
}

std::vector<double> IdaIntegrator::weightedErrors() const {
  void *mem = impl_->mem;
  long steps = 0;
  if (IDAGetNumSteps(mem, &steps) < 0)
    steps = 0;
  return sundials::weightedErrors(
      impl_->y, ev_.n(), steps,
      [&](N_Vector w) { return IDAGetErrWeights(mem, w); },
      [&](N_Vector e) { return IDAGetEstLocalErrors(mem, e); });
}

double IdaIntegrator::currentTime() const {
  return sundials::valueOrZero(
      [&](double *v) { return IDAGetCurrentTime(impl_->mem, v); });
}

double IdaIntegrator::lastStep() const {
  return sundials::valueOrZero(
      [&](double *v) { return IDAGetLastStep(impl_->mem, v); });
}

double IdaIntegrator::iterationCj() const {
  return sundials::valueOrZero(
      [&](double *v) { return IDAGetCurrentCj(impl_->mem, v); });
}

} // namespace ldae::runtime
