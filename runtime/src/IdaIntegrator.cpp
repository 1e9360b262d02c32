// IDA set-up and stepping for an ldae_model (see IdaIntegrator.h). Every
// SUNDIALS return value is checked; IDA's own error printing is replaced by
// a handler that keeps the last message for our failure report.
#include "IdaIntegrator.h"

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

using Data = IdaIntegrator::CallbackData;

int residualFn(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void *user) {
  auto *d = static_cast<Data *>(user);
  int rc = d->ev->residual(d->set, t, N_VGetArrayPointer(y),
                           N_VGetArrayPointer(yp), N_VGetArrayPointer(r));
  if (rc > 0) {
    // A domain error: recoverable, IDA retries with a smaller step. Remember
    // the row so the failure message can name the equation.
    d->domainRow = rc - 1;
    const double *py = N_VGetArrayPointer(y);
    d->domainY.assign(py, py + d->ev->n());
    return 1;
  }
  return rc < 0 ? -1 : 0;
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
  sunindextype *colptr = SUNSparseMatrix_IndexPointers(J);
  sunindextype *rowind = SUNSparseMatrix_IndexValues(J);
  for (int c = 0; c <= n; ++c)
    colptr[c] = s.jac_colptr[c];
  for (int q = 0; q < s.jac_nnz; ++q)
    rowind[q] = s.jac_rowind[q];
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

void errHandler(int code, const char *module, const char *function, char *msg,
                void *user) {
  auto *d = static_cast<Data *>(user);
  d->idaMessage = fmt::format("{} ({}): {}", function, code, msg);
}

Error sundialsError(const char *call, int flag) {
  return Error{
      fmt::format("internal error: {} failed with flag {}", call, flag)};
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
    : ev_(ev), impl_(std::make_unique<Impl>()) {
  data_.ev = &ev;
}

IdaIntegrator::~IdaIntegrator() = default;

#define LDAE_CHECK(call)                                                       \
  do {                                                                         \
    int flag_ = (call);                                                        \
    if (flag_ < 0)                                                             \
      return sundialsError(#call, flag_);                                      \
  } while (0)

Expected<bool> IdaIntegrator::init(int set, double t0, const double *y,
                                   const double *yp, double rtol,
                                   const std::vector<double> &atol,
                                   double tstop, bool suppressAlg) {
  Impl &I = *impl_;
  int n = ev_.n();
  data_.set = set;
  LDAE_CHECK(SUNContext_Create(nullptr, &I.ctx));
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
  LDAE_CHECK(IDASetErrHandlerFn(I.mem, errHandler, &data_));
  LDAE_CHECK(IDAInit(I.mem, residualFn, t0, I.y, I.yp));
  LDAE_CHECK(IDASetUserData(I.mem, &data_));
  LDAE_CHECK(IDASVtolerances(I.mem, rtol, I.atol));
  I.tstop = tstop;
  LDAE_CHECK(IDASetStopTime(I.mem, tstop));
  const ldae_model &m = ev_.model();
  if (m.n_roots > 0 && m.roots)
    LDAE_CHECK(IDARootInit(I.mem, m.n_roots, rootFn));
  auto ok = setupId();
  if (!ok)
    return ok;
  // Index-1 theory: the algebraic components are functions of the
  // differential ones, so their error follows; testing them only forces
  // needlessly small steps (and fails outright for dummy derivatives).
  LDAE_CHECK(IDASetSuppressAlg(I.mem, suppressAlg ? SUNTRUE : SUNFALSE));
  return setupLinearSolver();
}

Expected<bool> IdaIntegrator::setupId() {
  const ldae_state_set &s = ev_.set(data_.set);
  double *id = N_VGetArrayPointer(impl_->id);
  for (int i = 0; i < ev_.n(); ++i)
    id[i] = s.is_differential[i] ? 1.0 : 0.0;
  LDAE_CHECK(IDASetId(impl_->mem, impl_->id));
  return true;
}

Expected<bool> IdaIntegrator::setupLinearSolver() {
  Impl &I = *impl_;
  const ldae_state_set &s = ev_.set(data_.set);
  int n = ev_.n();
  bool sparse = n > LDAE_DENSE_THRESHOLD && s.jacobian_csc && s.jac_colptr;
  if (I.LS && !sparse && !sparse_) {
    // Dense to dense: the matrix and solver stay; only the Jacobian source
    // changes (IDA's difference quotients when the set has none).
    LDAE_CHECK(IDASetJacFn(I.mem, s.jacobian_dense ? denseJacFn : nullptr));
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
    return sundialsError("IDASetLinearSolver", flag);
  }
  I.freeSolver();
  I.A = A;
  I.LS = LS;
  sparse_ = sparse;
  if (sparse)
    LDAE_CHECK(IDASetJacFn(I.mem, sparseJacFn));
  else
    LDAE_CHECK(IDASetJacFn(I.mem, s.jacobian_dense ? denseJacFn : nullptr));
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
  int n = ev_.n();
  std::copy(y, y + n, N_VGetArrayPointer(I.y));
  std::copy(yp, yp + n, N_VGetArrayPointer(I.yp));
  int oldSet = data_.set;
  data_.set = set;
  LDAE_CHECK(IDAReInit(I.mem, t, I.y, I.yp));
  LDAE_CHECK(IDASetStopTime(I.mem, I.tstop));
  auto ok = setupId();
  if (!ok)
    return ok;
  if (oldSet != set)
    return setupLinearSolver();
  return true;
}

int IdaIntegrator::calcIC(double tout1) {
  Impl &I = *impl_;
  int flag = IDACalcIC(I.mem, IDA_YA_YDP_INIT, tout1);
  if (flag < 0)
    return flag;
  int g = IDAGetConsistentIC(I.mem, I.y, I.yp);
  return g < 0 ? g : flag;
}

Expected<bool> IdaIntegrator::setStopTime(double tstop) {
  impl_->tstop = tstop;
  LDAE_CHECK(IDASetStopTime(impl_->mem, tstop));
  return true;
}

int IdaIntegrator::step(double &tret) {
  Impl &I = *impl_;
  int flag = IDASolve(I.mem, I.tstop, &tret, I.y, I.yp, IDA_ONE_STEP);
  if (flag == IDA_ROOT_RETURN)
    ++I.rootCount;
  return flag;
}

Expected<bool> IdaIntegrator::dky(double t, int k, double *out) {
  Impl &I = *impl_;
  LDAE_CHECK(IDAGetDky(I.mem, t, k, I.tmp));
  const double *src = N_VGetArrayPointer(I.tmp);
  std::copy(src, src + ev_.n(), out);
  return true;
}

const double *IdaIntegrator::y() const { return N_VGetArrayPointer(impl_->y); }
const double *IdaIntegrator::yp() const {
  return N_VGetArrayPointer(impl_->yp);
}

std::vector<int> IdaIntegrator::rootsFound() const {
  const ldae_model &m = ev_.model();
  std::vector<int> found(std::max(m.n_roots, 0));
  if (!found.empty() && IDAGetRootInfo(impl_->mem, found.data()) < 0)
    found.assign(found.size(), 0);
  return found;
}

std::vector<double> IdaIntegrator::weightedErrors() const {
  int n = ev_.n();
  std::vector<double> out(n, 0.0);
  N_Vector w = N_VClone(impl_->y), e = N_VClone(impl_->y);
  if (w && e && IDAGetErrWeights(impl_->mem, w) >= 0 &&
      IDAGetEstLocalErrors(impl_->mem, e) >= 0) {
    const double *pw = N_VGetArrayPointer(w), *pe = N_VGetArrayPointer(e);
    for (int i = 0; i < n; ++i)
      out[i] = std::abs(pw[i] * pe[i]);
  }
  if (w)
    N_VDestroy(w);
  if (e)
    N_VDestroy(e);
  return out;
}

double IdaIntegrator::currentTime() const {
  double t = 0;
  if (IDAGetCurrentTime(impl_->mem, &t) < 0)
    return 0;
  return t;
}

double IdaIntegrator::lastStep() const {
  double h = 0;
  if (IDAGetLastStep(impl_->mem, &h) < 0)
    return 0;
  return h;
}

double IdaIntegrator::currentCj() const {
  double cj = 0;
  if (IDAGetCurrentCj(impl_->mem, &cj) < 0)
    return 0;
  return cj;
}

} // namespace ldae::runtime
