// CVODE set-up and stepping for an explicit-ODE or a linearly implicit
// ldae_model (see CvodeIntegrator.h). Every SUNDIALS return value is
// checked; CVODE's own error printing is replaced by a handler that keeps
// the last message.
#include "integrators/CvodeIntegrator.h"
#include "integrators/ConstraintProjection.h"
#include "integrators/ImplicitOde.h"
#include "integrators/SgaProjectionPolicy.h"
#include "integrators/StiffnessDetector.h"
#include "integrators/SundialsSupport.h"

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
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

/// CVODE's user data: the callbacks shared with IDA, and for a linearly
/// implicit model its vector field and projection.
struct Callbacks {
  Data *d = nullptr;
  ImplicitOde *implicit = nullptr;         // null: an explicit ODE
  ConstraintProjection *projection = nullptr;
  bool singular = false; // dF/dy' was singular at a trial point
  double stabilize = 0;
  std::vector<double> ybuf;
};

/// f(t, y): -F(t, y, 0) for an explicit ODE (row i is y'[i] - f_i(t, y)),
/// else the solution of the linearly implicit rows.
int evalRhs(Callbacks &c, double t, const double *y, double *ydot) {
  if (c.implicit) {
    int rc = c.implicit->rhs(t, y, ydot);
    if (rc == ImplicitOde::kSingular)
      c.singular = true;
    if (rc == 0 && c.stabilize > 0) {
      c.ybuf.resize(c.d->ev->n());
      rc = c.projection->correction(t, y, c.ybuf.data());
      for (int i = 0; rc == 0 && i < c.d->ev->n(); ++i)
        ydot[i] += c.stabilize * c.ybuf[i];
    }
    return rc;
  }
  const Data &d = *c.d;
  int rc = d.ev->residual(d.set, t, y, d.zeros.data(), ydot);
  if (rc == 0)
    for (int i = 0; i < d.ev->n(); ++i)
      ydot[i] = -ydot[i];
  return rc;
}

int rhsFn(sunrealtype t, N_Vector y, N_Vector ydot, void *user) {
  auto *c = static_cast<Callbacks *>(user);
  Data *d = c->d;
  const double *py = N_VGetArrayPointer(y);
  double *pf = N_VGetArrayPointer(ydot);
  int n = d->ev->n();
  if (!Integrator::finite(py, n)) {
    d->nonFinite = true;
    return 1;
  }
  int raw = evalRhs(*c, t, py, pf);
  if (raw == ImplicitOde::kSingular)
    return 1; // recoverable: a smaller step stays nearer the manifold
  int rc = Integrator::callbackStatus(*d, raw, py);
  if (rc == 0 && !Integrator::finite(pf, n)) {
    d->nonFinite = true;
    return 1;
  }
  return rc;
}

int abiStatus(int rc) { return rc > 0 ? 1 : (rc < 0 ? -1 : 0); }

/// df/dy = -dF/dy: the model's Jacobian at cj = 0, negated.
int denseJacFn(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J,
               void *user, N_Vector, N_Vector, N_Vector) {
  auto *c = static_cast<Callbacks *>(user);
  const Data *d = c->d;
  double *a = SUNDenseMatrix_Data(J);
  if (c->implicit)
    return abiStatus(c->implicit->jacobian(t, N_VGetArrayPointer(y),
                                           N_VGetArrayPointer(fy), a));
  const ldae_state_set &s = d->ev->set(d->set);
  int rc = s.jacobian_dense(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                            d->ev->params(), 0.0, a);
  long n = long(d->ev->n());
  for (long k = 0; k < n * n; ++k)
    a[k] = -a[k];
  return abiStatus(rc);
}

int sparseJacFn(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J,
                void *user, N_Vector, N_Vector, N_Vector) {
  const Data *d = static_cast<Callbacks *>(user)->d;
  const ldae_state_set &s = d->ev->set(d->set);
  int n = d->ev->n();
  sundials::copyPattern(J, s, n);
  double *a = SUNSparseMatrix_Data(J);
  int rc = s.jacobian_csc(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                          d->ev->params(), 0.0, a);
  for (int q = 0; q < s.jac_nnz; ++q)
    a[q] = -a[q];
  return abiStatus(rc);
}

/// CVODE's projection after each step (BDF only in SUNDIALS 6.4): the
/// Gauss-Newton correction onto the constraints, and the error estimate's
/// normal component removed.
int projFn(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype,
           N_Vector err, void *user) {
  auto *c = static_cast<Callbacks *>(user);
  const double *py = N_VGetArrayPointer(ycur);
  c->ybuf.assign(py, py + c->d->ev->n());
  int rc = c->projection->project(t, c->ybuf.data(), false,
                                  N_VGetArrayPointer(corr));
  if (rc == 0 && err)
    c->projection->projectError(N_VGetArrayPointer(err));
  return abiStatus(rc);
}

/// CVEwtFn: the error weights at the step's starting point, with y' = f.
int ewtFn(N_Vector y, N_Vector ewt, void *user) {
  auto *c = static_cast<Callbacks *>(user);
  Data *d = c->d;
  const double *py = N_VGetArrayPointer(y);
  d->weightsYp.resize(d->ev->n());
  if (evalRhs(*c, d->t, py, d->weightsYp.data()) != 0)
    std::fill(d->weightsYp.begin(), d->weightsYp.end(), 0.0);
  d->weights->compute(d->t, py, d->weightsYp.data(), N_VGetArrayPointer(ewt));
  return 0;
}

int rootFn(sunrealtype t, N_Vector y, sunrealtype *g, void *user) {
  auto *c = static_cast<Callbacks *>(user);
  Data *d = c->d;
  const double *py = N_VGetArrayPointer(y);
  if (evalRhs(*c, t, py, d->work.data()) != 0)
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
  double tstop = 0, rtol = 0, hmax = 0;
  int rootCount = 0;
  bool rootReturned = false; // the last step returned a root, no restart since
  /// y' = f(t, y) at the current point, computed when first asked for.
  mutable std::vector<double> yp;
  mutable bool ypValid = false;
  /// The current point projected onto the constraints (sga), likewise.
  mutable std::vector<double> yOn;
  mutable bool yOnValid = false;
  double t = 0;
  Callbacks cb;
  std::unique_ptr<ImplicitOde> implicit;
  std::unique_ptr<SgaProjectionPolicy> sga;
  std::vector<double> pendingRestart; // the projected point to restart at
  double pendingT = 0;
  bool pendingSwitch = false; // Adams to BDF at the next step
  StiffnessDetector stiffness;

  void freeSolver() {
    if (mem)
      CVodeFree(&mem);
    if (NLS)
      SUNNonlinSolFree(NLS);
    if (LS)
      SUNLinSolFree(LS);
    if (A)
      SUNMatDestroy(A);
    mem = nullptr;
    NLS = nullptr;
    LS = nullptr;
    A = nullptr;
  }
  ~Impl() {
    freeSolver();
    for (N_Vector v : {y, atol, tmp})
      if (v)
        N_VDestroy(v);
    if (ctx)
      SUNContext_Free(&ctx);
  }
};

CvodeIntegrator::CvodeIntegrator(const ModelEval &ev, Lmm lmm)
    : Integrator(ev), impl_(std::make_unique<Impl>()),
      adams_(lmm != Lmm::Bdf), autoChoice_(lmm == Lmm::Auto) {
  shared_.ev = &ev;
  shared_.zeros.assign(ev.n(), 0.0);
  shared_.work.assign(ev.n(), 0.0);
  impl_->yp.assign(ev.n(), 0.0);
  impl_->yOn.assign(ev.n(), 0.0);
  impl_->cb.d = &shared_;
  const ldae_model &m = ev.model();
  if (m.n_ode == m.n && m.n > 0) {
    impl_->implicit = std::make_unique<ImplicitOde>(ev);
    impl_->cb.implicit = impl_->implicit.get();
    impl_->sga = std::make_unique<SgaProjectionPolicy>(ev);
    impl_->cb.projection = &impl_->sga->projection();
    project_ = m.project_constraints != 0 && impl_->sga->active();
  }
  // Above this size the spectrum costs more than it can save: BDF.
  if (autoChoice_ && !StiffnessDetector::affordable(ev.n())) {
    adams_ = false;
    autoChoice_ = false;
  }
  updateName();
}

CvodeIntegrator::~CvodeIntegrator() = default;

void CvodeIntegrator::updateName() {
  name_ = switched_ ? "CVODE (Adams, then BDF)"
                    : adams_ ? "CVODE (Adams)" : "CVODE (BDF)";
  if (impl_->implicit)
    name_ += project_ ? ", projected onto the constraints"
                      : ", linearly implicit";
}

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
  I.rtol = rtol;
  I.tstop = tstop;
  return create(t0);
}

Expected<bool> CvodeIntegrator::create(double t0) {
  Impl &I = *impl_;
  I.t = t0;
  I.ypValid = false;
  I.yOnValid = false;
  I.mem = CVodeCreate(adams_ ? CV_ADAMS : CV_BDF, I.ctx);
  if (!I.mem)
    return Error{"internal error: CVodeCreate failed"};
  LDAE_SUNDIALS_CHECK(CVodeSetErrHandlerFn(I.mem, sundials::keepMessage, &shared_));
  LDAE_SUNDIALS_CHECK(CVodeInit(I.mem, rhsFn, t0, I.y));
  LDAE_SUNDIALS_CHECK(CVodeSetUserData(I.mem, &I.cb));
  shared_.t = t0;
  if (shared_.weights)
    LDAE_SUNDIALS_CHECK(CVodeWFtolerances(I.mem, ewtFn));
  else
    LDAE_SUNDIALS_CHECK(CVodeSVtolerances(I.mem, I.rtol, I.atol));
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(I.mem, I.tstop));
  LDAE_SUNDIALS_CHECK(CVodeSetMaxStep(I.mem, I.hmax));
  const ldae_model &m = ev_.model();
  if (m.n_roots > 0 && m.roots)
    LDAE_SUNDIALS_CHECK(CVodeRootInit(I.mem, m.n_roots, rootFn));
  if (project_ && !adams_)
    LDAE_SUNDIALS_CHECK(CVodeSetProjFn(I.mem, projFn));
  if (!project_ || !adams_)
    I.cb.stabilize = 0;
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
  // A linearly implicit model's df/dy = -E^-1 dF/dy is dense.
  bool sparse = !I.implicit && n > LDAE_DENSE_THRESHOLD && s.jacobian_csc &&
                s.jac_colptr;
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
    LDAE_SUNDIALS_CHECK(CVodeSetJacFn(
        I.mem, I.implicit || s.jacobian_dense ? denseJacFn : nullptr));
  return true;
}

void CvodeIntegrator::saveCounters() {
  SimStats now;
  addCounters(now);
  saved_ = now; // CVodeReInit zeroes CVODE's counters, CVodeFree loses them
  saved_.projections = 0; // the projection counts every call itself
  impl_->rootCount = 0;
}

Expected<bool> CvodeIntegrator::restartAt(double t, const double *y) {
  Impl &I = *impl_;
  saveCounters();
  I.rootReturned = false;
  std::copy(y, y + ev_.n(), N_VGetArrayPointer(I.y));
  I.t = t;
  I.ypValid = false;
  I.yOnValid = false;
  shared_.t = t;
  LDAE_SUNDIALS_CHECK(CVodeReInit(I.mem, t, I.y));
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(I.mem, I.tstop));
  return true;
}

Expected<bool> CvodeIntegrator::reinit(int set, double t, const double *y,
                                       const double *yp) {
  if (set != shared_.set)
    return Error{"internal error: CVODE runs a model with one state set"};
  impl_->pendingRestart.clear();
  if (!impl_->sga || !impl_->sga->active())
    return restartAt(t, y);
  // After an event, seed 002's rule: the point jumps onto the constraints
  // of the mode it entered along T(E, F) of the model as written (two
  // capacitors joined keep their charge; a mass that sticks keeps its
  // position, only the friction force jumps). The SGA's own rows have a
  // nonsingular E: their T is empty. Where the constraints cannot be met
  // along T, the start's rule below takes the nearest point.
  std::vector<double> on(y, y + ev_.n());
  const bool afterEvent = std::exchange(afterEvent_, false);
  if (afterEvent) {
    stepped_ = true; // the run goes on: its fixed start values are free
    // Where holding the reinit targets leaves no step along T: the
    // nearest point with them held (the dd rule); else the start's rule.
    if (!impl_->sga->jumpOntoConstraints(t, on.data(), yp, heldAfterEvent_,
                                         field()) &&
        !heldAfterEvent_.empty())
      impl_->sga->projection().projectHolding(t, on.data(), heldAfterEvent_);
  }
  // A point handed over from outside (the initialization's own Newton
  // iteration, an event's re-initialization) need only solve the rows: it
  // goes onto P_f by the start's rule first, else CVODE's first
  // projection fails from it.
  if (StepStatus st = startOnConstraints(t, on.data()); !st.ok())
    return Error{fmt::format("the point at t = {:.10g} cannot be projected "
                             "onto the constraints",
                             t)};
  return restartAt(t, on.data());
}

SgaProjectionPolicy::Field CvodeIntegrator::field() {
  return [this](double t, const double *y, double *f) {
    return evalRhs(impl_->cb, t, y, f);
  };
}

StepStatus CvodeIntegrator::startOnConstraints(double t, double *y) {
  Impl &I = *impl_;
  // Fixed start values are conditions and stay (at the start only).
  int rc = I.sga->projection().projectStart(t, y, !stepped_);
  if (rc != 0) {
    if (rc != ConstraintProjection::kNoConvergence && rc > 0)
      callbackStatus(shared_, rc, y);
    return StepStatus::failed(FailureKind::NoStart,
                              "projection onto the constraints");
  }
  if (project_ && adams_ && I.sga->stabilizeAt(*I.implicit, t, y))
    I.cb.stabilize = I.sga->stabilization();
  return {};
}

StepStatus CvodeIntegrator::completeStart(double) {
  Impl &I = *impl_;
  double *y = N_VGetArrayPointer(I.y);
  if (I.sga && I.sga->active()) {
    if (!stepped_)
      I.sga->jumpOntoConstraints(I.t, y, nullptr, I.sga->fixedUnknowns(),
                                 field());
    if (StepStatus st = startOnConstraints(I.t, y); !st.ok())
      return st;
    if (auto re = restartAt(I.t, y); !re)
      return StepStatus::failed(FailureKind::NoStart, re.error());
  }
  int rc = evalRhs(I.cb, I.t, y, I.yp.data());
  if (rc != 0) {
    if (rc != ImplicitOde::kSingular)
      callbackStatus(shared_, rc, y);
    return StepStatus::failed(rc == ImplicitOde::kSingular
                                  ? FailureKind::LinearSetup
                              : rc > 0 ? FailureKind::Domain
                                       : FailureKind::NoStart,
                              rc == ImplicitOde::kSingular
                                  ? "dF/dy' singular"
                                  : "CV_FIRST_RHSFUNC_ERR");
  }
  I.ypValid = true;
  return {};
}

Expected<bool> CvodeIntegrator::setMaxStep(double hmax) {
  impl_->hmax = hmax; // a new CVODE (switchToBdf) gets it too
  LDAE_SUNDIALS_CHECK(CVodeSetMaxStep(impl_->mem, hmax));
  return true;
}

Expected<bool> CvodeIntegrator::setStopTime(double tstop) {
  impl_->tstop = tstop;
  LDAE_SUNDIALS_CHECK(CVodeSetStopTime(impl_->mem, tstop));
  return true;
}

bool CvodeIntegrator::inspectSpectrum() {
  Impl &I = *impl_;
  Eigen::MatrixXd J;
  Eigen::VectorXcd lambda;
  if (!StiffnessDetector::affordable(ev_.n()) ||
      !I.implicit->linearization(I.t, N_VGetArrayPointer(I.y), J, lambda))
    return false;
  if (project_ && I.cb.stabilize > 0) {
    I.sga->raiseStabilization(lambda);
    I.cb.stabilize = I.sga->stabilization();
  }
  if (!autoChoice_)
    return false;
  return StiffnessDetector::looksStiff(lambda, lastStep(), I.tstop - I.t);
}

Expected<bool> CvodeIntegrator::switchToBdf() {
  Impl &I = *impl_;
  saveCounters();
  I.freeSolver();
  adams_ = false;
  switched_ = true;
  updateName();
  if (project_)
    I.sga->projection().project(I.t, N_VGetArrayPointer(I.y), false);
  return create(I.t);
}

StepStatus CvodeIntegrator::afterAdamsStep(double t) {
  Impl &I = *impl_;
  if (project_) {
    std::vector<double> restart;
    auto weights = [&]() -> const double * {
      return CVodeGetErrWeights(I.mem, I.tmp) < 0 ? nullptr
                                                  : N_VGetArrayPointer(I.tmp);
    };
    switch (I.sga->checkDrift(t, N_VGetArrayPointer(I.y), weights, restart)) {
    case SgaProjectionPolicy::Drift::Failed:
      return StepStatus::failed(FailureKind::Convergence,
                                "projection onto the constraints");
    case SgaProjectionPolicy::Drift::Restart:
      I.pendingRestart = std::move(restart);
      I.pendingT = t;
      break;
    case SgaProjectionPolicy::Drift::Within:
      break;
    }
  }
  if ((autoChoice_ || project_) && I.stiffness.due())
    I.pendingSwitch = inspectSpectrum(); // at the next step, as a restart
  return {};
}

StepStatus CvodeIntegrator::step(double &tret) {
  Impl &I = *impl_;
  if (I.pendingSwitch) {
    I.pendingSwitch = false;
    I.pendingRestart.clear(); // the switch projects too
    if (!switchToBdf())
      return StepStatus::failed(FailureKind::Other, "switch to BDF");
  }
  if (!I.pendingRestart.empty()) {
    std::vector<double> y = std::move(I.pendingRestart);
    I.pendingRestart.clear();
    if (!restartAt(I.pendingT, y.data()))
      return StepStatus::failed(FailureKind::Other, "CVodeReInit");
  }
  shared_.nonFinite = false;
  I.cb.singular = false;
  int flag = CVode(I.mem, oneStepTarget(I.t, I.tstop), I.y, &tret, CV_ONE_STEP);
  auto closeRoots = [&] {
    return flag == CV_ILL_INPUT && ev_.model().n_roots > 0 &&
           shared_.message.find("cvRcheck2") != std::string::npos;
  };
  if (closeRoots() && I.rootReturned) {
    // Going on from the root it returned, a root function it watches is
    // exactly zero there and just past it: restarted at the root, CVODE
    // sets it aside until it leaves zero (as IdaIntegrator::step does).
    const std::vector<double> y(N_VGetArrayPointer(I.y),
                                N_VGetArrayPointer(I.y) + ev_.n());
    if (!restartAt(I.t, y.data()))
      return StepStatus::failed(FailureKind::Other, "CVodeReInit");
    flag = CVode(I.mem, oneStepTarget(I.t, I.tstop), I.y, &tret, CV_ONE_STEP);
  }
  if (closeRoots()) {
    // Restarted exactly on a root function's zero, and it is still zero
    // (to round-off) a hair later: a slow relation just after its event
    // (hysteresis: T = 294 K at T' = 7 K/s, rtol 1e-12). CVODE refuses
    // to start its root search there; one step without roots moves off
    // the zero, then the search starts again from that step.
    // (The first step after a restart is short: a crossing inside it is
    // the one price.)
    if (CVodeRootInit(I.mem, 0, nullptr) < 0)
      return StepStatus::failed(FailureKind::Other, "CVodeRootInit");
    flag = CVode(I.mem, oneStepTarget(I.t, I.tstop), I.y, &tret, CV_ONE_STEP);
    if (CVodeRootInit(I.mem, ev_.model().n_roots, rootFn) < 0)
      return StepStatus::failed(FailureKind::Other, "CVodeRootInit");
  }
  I.rootReturned = flag == CV_ROOT_RETURN;
  I.ypValid = false;
  I.yOnValid = false;
  if (flag < 0) {
    StepStatus st = overflowAware(failure(flag));
    if (I.cb.singular && st.failure == FailureKind::Domain &&
        shared_.domainRow < 0)
      return StepStatus::failed(FailureKind::LinearSetup,
                                "dF/dy' singular");
    return st;
  }
  I.t = tret;
  shared_.t = tret;
  stepped_ = true;
  if (adams_ && I.implicit) {
    StepStatus after = afterAdamsStep(tret);
    if (!after.ok())
      return after;
  }
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
  // The interpolating polynomial meets the constraints only to its own
  // error: rows of the geometric method are projected as the steps are.
  if (project_ && I.sga->projection().project(t, y, false) != 0)
    return Error{fmt::format("the interpolated point at the output time "
                             "{:.10g} cannot be projected onto the "
                             "constraints",
                             t)};
  // The derivative from f at the interpolated point, not the polynomial's:
  // outputs that read y' then satisfy the equations.
  if (evalRhs(I.cb, t, y, yp) != 0)
    return Error{fmt::format("the right-hand side cannot be evaluated at the "
                             "output time {:.10g}",
                             t)};
  return true;
}

const double *CvodeIntegrator::y() const {
  Impl &I = *impl_;
  const double *y = N_VGetArrayPointer(I.y);
  if (!project_ || !adams_)
    return y; // BDF's steps are projected by CVODE itself
  if (!I.yOnValid) {
    std::copy(y, y + ev_.n(), I.yOn.begin());
    if (I.sga->projection().project(I.t, I.yOn.data(), false) != 0)
      std::copy(y, y + ev_.n(), I.yOn.begin());
    I.yOnValid = true;
  }
  return I.yOn.data();
}

const double *CvodeIntegrator::yp() const {
  Impl &I = *impl_;
  if (!I.ypValid) {
    if (evalRhs(I.cb, I.t, y(), I.yp.data()) != 0)
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
  if (impl_->sga)
    st.projections += impl_->sga->projection().count(); // all restarts
}

std::vector<int> CvodeIntegrator::rootsFound() const {
  return sundials::rootInfo(ev_.model().n_roots, [&](int *found) {
    return CVodeGetRootInfo(impl_->mem, found);
  });
}

std::vector<double> CvodeIntegrator::weightedErrors() const {
  void *mem = impl_->mem;
  long steps = 0;
  if (CVodeGetNumSteps(mem, &steps) < 0)
    steps = 0;
  return sundials::weightedErrors(
      impl_->y, ev_.n(), steps,
      [&](N_Vector w) { return CVodeGetErrWeights(mem, w); },
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
