// Failure messages for IDA's error returns (see FailureReport.h).
#include "FailureReport.h"
#include "ConsistentInit.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <ida/ida.h>
#include <numeric>

namespace ldae::runtime {

namespace {

struct FlagInfo {
  const char *name;
  const char *what;
  const char *hint;
};

FlagInfo flagInfo(int flag) {
  switch (flag) {
  case IDA_TOO_MUCH_WORK:
    return {"IDA_TOO_MUCH_WORK",
            "too many steps without reaching the output "
            "time",
            "the model may be stiff or oscillate fast; loosen --rtol or "
            "shorten --stop"};
  case IDA_TOO_MUCH_ACC:
    return {"IDA_TOO_MUCH_ACC", "the requested accuracy cannot be reached",
            "loosen --rtol and --atol"};
  case IDA_ERR_FAIL:
    return {"IDA_ERR_FAIL",
            "the error test failed repeatedly with the "
            "smallest step",
            "tighten or loosen --rtol; the model may be high index (try "
            "--method dd) or have a discontinuity"};
  case IDA_CONV_FAIL:
    return {"IDA_CONV_FAIL",
            "the Newton iteration failed to converge "
            "repeatedly",
            "the model may be high index (try --method dd); check the start "
            "values; tighten --rtol"};
  case IDA_LSETUP_FAIL:
    return {"IDA_LSETUP_FAIL", "the iteration matrix is singular",
            "the model may be high index; try --method dd"};
  case IDA_LSOLVE_FAIL:
    return {"IDA_LSOLVE_FAIL", "the linear solve failed",
            "the model may be high index; try --method dd"};
  case IDA_RES_FAIL:
  case IDA_REP_RES_ERR:
    return {flag == IDA_RES_FAIL ? "IDA_RES_FAIL" : "IDA_REP_RES_ERR",
            "an equation left its domain (e.g. sqrt or log of a negative "
            "number) and smaller steps did not help",
            "check the start values and parameters; the solution may really "
            "leave the domain here"};
  case IDA_RTFUNC_FAIL:
    return {"IDA_RTFUNC_FAIL", "an event condition could not be evaluated",
            "check the event conditions"};
  case IDA_NO_RECOVERY:
  case IDA_LINESEARCH_FAIL:
  case IDA_FIRST_RES_FAIL:
    return {flag == IDA_NO_RECOVERY       ? "IDA_NO_RECOVERY"
            : flag == IDA_LINESEARCH_FAIL ? "IDA_LINESEARCH_FAIL"
                                          : "IDA_FIRST_RES_FAIL",
            "no consistent initial point was found", "check the start values"};
  case kStepCollapsed:
    return {"step size collapse", "the step size fell to round-off level",
            "the solution may leave an equation's domain or have a "
            "singularity here; check the start values and parameters"};
  default:
    return {"IDA error", "the integrator stopped", "tighten or loosen --rtol"};
  }
}

/// The (at most three) indices of the largest |u_i|, those above a tenth
/// of the largest, largest first.
std::vector<int> dominantRows(const Eigen::VectorXd &u) {
  std::vector<int> rows;
  double top = u.size() ? u.cwiseAbs().maxCoeff() : 0.0;
  for (int i = 0; i < u.size(); ++i)
    if (std::fabs(u(i)) > 0.1 * top)
      rows.push_back(i);
  std::sort(rows.begin(), rows.end(), [&](int a, int b) {
    return std::fabs(u(a)) > std::fabs(u(b));
  });
  if (rows.size() > 3)
    rows.resize(3);
  return rows;
}

/// Sparse counterpart for large models (a dense SVD is O(n^3)): KLU on
/// J^T. A zero pivot names a row of J directly; otherwise, when the
/// condition estimate says singular, a few steps of inverse iteration with
/// J^T approximate the left singular vector of the smallest singular value.
std::vector<int> singularRowsSparse(const ModelEval &ev,
                                    const IdaIntegrator &ida, double t) {
  CscMatrix J;
  if (ev.jacobianCsc(ida.set(), t, ida.y(), ida.yp(), ida.currentCj(), J) !=
      0)
    return {};
  CscMatrix Jt = J.transposed();
  SparseLu lu;
  if (!lu.factor(Jt)) {
    int row = lu.singularColumn();
    return row >= 0 ? std::vector<int>{row} : std::vector<int>{};
  }
  if (lu.rcondEstimate() > 1e-10)
    return {};
  Eigen::VectorXd u = Eigen::VectorXd::Ones(J.n);
  for (int it = 0; it < 3; ++it) {
    if (!lu.solve(u.data()) || !u.allFinite() || u.norm() == 0)
      return {};
    u.normalize();
  }
  return dominantRows(u);
}

/// The rows a (near) singular iteration matrix singles out: the largest
/// components of the left singular vector of its smallest singular value.
std::vector<int> singularRows(const ModelEval &ev, const IdaIntegrator &ida,
                              double t) {
  if (usesSparseInit(ev))
    return singularRowsSparse(ev, ida, t);
  Eigen::MatrixXd J;
  double cj = ida.currentCj();
  if (ev.jacobian(ida.set(), t, ida.y(), ida.yp(), cj, J) != 0 || J.size() == 0)
    return {};
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullU);
  Eigen::VectorXd sv = svd.singularValues();
  if (sv(sv.size() - 1) > 1e-10 * sv(0))
    return {};
  return dominantRows(svd.matrixU().col(sv.size() - 1));
}

std::string worstVariables(const ModelEval &ev, const IdaIntegrator &ida) {
  std::vector<double> err = ida.weightedErrors();
  std::vector<int> order(err.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return err[a] > err[b]; });
  std::string out;
  for (size_t i = 0; i < order.size() && i < 3; ++i) {
    if (!(err[order[i]] > 0))
      break;
    out += fmt::format("{}'{}' (weighted error {:.3g}, value {:.6g})",
                       i ? ", " : "", ev.varName(order[i]), err[order[i]],
                       ida.y()[order[i]]);
  }
  return out;
}

} // namespace

std::string describeFailure(const ModelEval &ev, const IdaIntegrator &ida,
                            int flag, double t) {
  FlagInfo info = flagInfo(flag);
  std::string msg = fmt::format("simulation failed at t = {:.10g}: {} ({})", t,
                                info.what, info.name);
  std::string worst = worstVariables(ev, ida);
  if (!worst.empty())
    msg += "\n  largest local errors: " + worst;
  std::vector<int> rows;
  if ((flag == IDA_RES_FAIL || flag == IDA_REP_RES_ERR ||
       flag == IDA_CONV_FAIL || flag == kStepCollapsed) &&
      ida.lastDomainRow() >= 0)
    rows.push_back(ida.lastDomainRow());
  else if (flag == IDA_LSETUP_FAIL || flag == IDA_CONV_FAIL ||
           flag == IDA_LSOLVE_FAIL)
    rows = singularRows(ev, ida, t);
  for (int r : rows)
    msg += "\n  in " + ev.describeRow(r);
  msg += fmt::format("\n  hint: {}", info.hint);
  return msg;
}

std::string describeInitFailure(const ModelEval &ev, const IdaIntegrator &ida,
                                int flag, double t) {
  std::string msg = fmt::format(
      "initialization failed at t = {:.10g}: no consistent initial point "
      "found (IDACalcIC: {})",
      t, flagInfo(flag).name);
  if (ida.lastDomainRow() >= 0)
    msg += "\n  in " + ev.describeRow(ida.lastDomainRow());
  msg += "\n  hint: check the start values";
  return msg;
}

} // namespace ldae::runtime
