// Failure messages for the integrators' error returns (see FailureReport.h).
#include "run/FailureReport.h"
#include "init/ConsistentInit.h"
#include "numeric/Rank.h"
#include "support/ModelicaErrorMessage.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <numeric>

namespace ldae::runtime {

namespace {

/// What "outside its domain" covers: the operations whose checks set a
/// residual's error bit (CodePlan.h), the common ones named (also in
/// failureText's Domain case).
constexpr const char *kDomainExamples =
    "(e.g. a division by zero, or sqrt or log of a negative number)";

/// A singular iteration matrix of a system of index one at most.
constexpr const char *kSingularHint =
    "the equations named may not determine their unknowns here (a fold, "
    "where the solution turns back, or a coefficient that vanishes); check "
    "the parameters and the start values";

struct FailureText {
  const char *what;
  const char *hint;
};

FailureText failureText(FailureKind kind) {
  switch (kind) {
  case FailureKind::TooMuchWork:
    return {"too many steps without reaching the output time",
            "the model may be stiff or oscillate fast; loosen --rtol or "
            "shorten --stop"};
  case FailureKind::TooMuchAccuracy:
    return {"the requested accuracy cannot be reached",
            "loosen --rtol and --atol"};
  // A high index is no cause here: the hints are for a system of index
  // one at most (every reduced one); describeFailure adds it for a system
  // handed over as written (--method raw) whose index exceeds one.
  case FailureKind::ErrorTest:
    return {"the error test failed repeatedly with the smallest step",
            "tighten or loosen --rtol; the model may have a discontinuity"};
  case FailureKind::Convergence:
    return {"the Newton iteration failed to converge repeatedly",
            "check the start values; tighten or loosen --rtol and --atol"};
  case FailureKind::LinearSetup:
    return {"the iteration matrix is singular", kSingularHint};
  case FailureKind::LinearSolve:
    return {"the linear solve failed", kSingularHint};
  case FailureKind::Domain:
    return {"an equation left its domain (e.g. a division by zero, or sqrt "
            "or log of a negative number) and smaller steps did not help",
            "check the start values and parameters; the solution may really "
            "leave the domain here"};
  case FailureKind::RootFunction:
    return {"an event condition could not be evaluated",
            "check the event conditions"};
  case FailureKind::NoStart:
    return {"no consistent initial point was found", "check the start values"};
  case FailureKind::StepCollapsed:
    return {"the step size fell to round-off level",
            "the solution may leave an equation's domain or have a "
            "singularity here; check the start values and parameters"};
  case FailureKind::Overflow:
    return {"the solution or its derivative is not finite (beyond the "
            "largest double)",
            "the solution grows out of range; check the parameters and the "
            "start values, or shorten --stop"};
  case FailureKind::Other:
    break;
  }
  return {"the integrator stopped", "tighten or loosen --rtol"};
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
                                    const Integrator &integrator, double t) {
  CscMatrix J;
  if (ev.jacobianCsc(integrator.set(), t, integrator.y(), integrator.yp(),
                     integrator.iterationCj(), J) != 0)
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
std::vector<int> singularRows(const ModelEval &ev, const Integrator &integrator,
                              double t) {
  if (usesSparseInit(ev))
    return singularRowsSparse(ev, integrator, t);
  Eigen::MatrixXd J;
  double cj = integrator.iterationCj();
  if (ev.jacobian(integrator.set(), t, integrator.y(), integrator.yp(), cj,
                  J) != 0 ||
      J.size() == 0)
    return {};
  Eigen::VectorXd u;
  if (!numeric::nearSingularLeftVector(J, 1e-10, u))
    return {};
  return dominantRows(u);
}

/// Splits "file:line[:col]" (the file may contain ':').
void splitOrigin(const std::string &origin, std::string &file, int &line,
                 int &col) {
  auto number = [](const std::string &t) {
    return !t.empty() && t.size() < 9 &&
           std::all_of(t.begin(), t.end(), [](char c) {
             return c >= '0' && c <= '9';
           });
  };
  file = origin;
  line = col = 0;
  size_t last = origin.rfind(':');
  if (last == std::string::npos || !number(origin.substr(last + 1)))
    return;
  size_t prev = origin.rfind(':', last - 1);
  if (last > 0 && prev != std::string::npos &&
      number(origin.substr(prev + 1, last - prev - 1))) {
    file = origin.substr(0, prev);
    line = std::stoi(origin.substr(prev + 1, last - prev - 1));
    col = std::stoi(origin.substr(last + 1));
  } else {
    file = origin.substr(0, last);
    line = std::stoi(origin.substr(last + 1));
  }
}

/// Line `line` (1-based) of `file`, or "" when it cannot be read. Only
/// reached on failure, so reading the file again costs nothing that matters.
std::string sourceLine(const std::string &file, int line) {
  std::ifstream in(file);
  std::string text;
  for (int i = 0; i < line && std::getline(in, text); ++i)
    if (i == line - 1)
      return text;
  return "";
}

/// Unknowns whose column of the state set's Jacobian pattern has `row`.
std::vector<int> unknownsRead(const ModelEval &ev, int set, int row) {
  const ldae_state_set &s = ev.set(set);
  std::vector<int> cols;
  if (!s.jac_colptr || !s.jac_rowind)
    return cols;
  for (int c = 0; c < ev.n(); ++c)
    for (int q = s.jac_colptr[c]; q < s.jac_colptr[c + 1]; ++q)
      if (s.jac_rowind[q] == row) {
        cols.push_back(c);
        break;
      }
  return cols;
}

/// At most this many values are listed: the equation is short, a long
/// list would hide the message.
constexpr size_t kMaxValuesListed = 8;

std::string worstVariables(const ModelEval &ev, const Integrator &integrator) {
  std::vector<double> err = integrator.weightedErrors();
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
                       integrator.y()[order[i]]);
  }
  return out;
}

} // namespace

/// The source line at `origin` ("file:line:col") with a caret under the
/// column, each on a line of its own; "" when the file cannot be read.
std::string sourceWithCaret(const std::string &origin) {
  std::string file;
  int line = 0, col = 0;
  splitOrigin(origin, file, line, col);
  std::string text = line > 0 ? sourceLine(file, line) : "";
  if (text.empty())
    return "";
  // Tabs keep their width under the caret.
  std::string pad;
  for (int i = 0; i + 1 < col && i < int(text.size()); ++i)
    pad += text[i] == '\t' ? '\t' : ' ';
  return "\n    " + text + "\n    " + pad + "^";
}

/// Where a domain error in a residual really happened when the residual
/// reads a variable causalization computes: the outputs function, at the
/// same point, fails first at that variable (its stores run in solve
/// order, so the variable holding the failing operation comes before the
/// ones computed from it). "" when no computed variable fails.
std::string computedCause(const ModelEval &ev, double t, const double *y,
                          const double *yp) {
  const ldae_model &m = ev.model();
  if (m.n_outputs <= 0 || !m.outputs || !m.output_origin)
    return "";
  std::vector<double> out(m.n_outputs), zeros(ev.n(), 0.0);
  int rc = m.outputs(t, y, yp ? yp : zeros.data(), ev.params(), out.data());
  if (rc <= 0 || rc > m.n_outputs || !m.output_origin[rc - 1] ||
      !*m.output_origin[rc - 1])
    return "";
  std::string origin = m.output_origin[rc - 1];
  return fmt::format("\n  while computing '{}' in the equation at {}",
                     m.output_names[rc - 1], origin) +
         sourceWithCaret(origin);
}

/// What external C code said when it failed (a ModelicaError), "" if
/// nothing: its call's NaN is the domain error being described.
std::string externalCodeMessage(std::string message) {
  return message.empty() ? "" : "\n  the external C code reported: " + message;
}

std::string describeDomainRow(const ModelEval &ev, int set, int row,
                              const double *y, double t, const double *yp) {
  std::string msg = "\n  in " + ev.describeRow(row) +
                    sourceWithCaret(ev.origin(row));
  std::string failed = takeModelicaError();
  if (!y)
    return msg + externalCodeMessage(failed);
  msg += computedCause(ev, t, y, yp);
  // computedCause's evaluation at the failure point says it again, if so.
  if (std::string again = takeModelicaError(); !again.empty())
    failed = again;
  msg += externalCodeMessage(failed);
  std::vector<int> cols = unknownsRead(ev, set, row);
  std::string values;
  for (size_t i = 0; i < cols.size() && i < kMaxValuesListed; ++i)
    values += fmt::format("{}'{}' = {:.10g}", i ? ", " : "",
                          ev.varName(cols[i]), y[cols[i]]);
  if (cols.size() > kMaxValuesListed)
    values += fmt::format(", ... ({} more)", cols.size() - kMaxValuesListed);
  if (!values.empty())
    msg += "\n  values: " + values;
  return msg;
}

std::string describeInitDomainError(const ModelEval &ev, int set, int row,
                                    const double *y, double t) {
  return fmt::format("initialization failed at t = {:.10g}: an equation is "
                     "outside its domain {} at the start values",
                     t, kDomainExamples) +
         describeDomainRow(ev, set, row, y, t, nullptr) +
         "\n  hint: check the start values and parameters";
}

std::string describeEventDomainError(const ModelEval &ev, int set, int row,
                                     const double *y, double t) {
  return fmt::format("the re-initialization after the event at t = {:.10g} "
                     "failed: an equation is outside its domain {} in the "
                     "mode the event entered",
                     t, kDomainExamples) +
         describeDomainRow(ev, set, row, y, t, nullptr) +
         "\n  hint: in this mode an equation may no longer determine the "
         "unknown it is solved for (a coefficient that is 0 here, such as a "
         "resistance of 0, divides by 0); check the parameters";
}

std::string describeOutputDomainError(const ModelEval &ev, int output,
                                     double t, double lastGood,
                                     const double *y) {
  const ldae_model &m = ev.model();
  std::string name = m.output_names && m.output_names[output]
                         ? m.output_names[output]
                         : fmt::format("output {}", output + 1);
  std::string msg = fmt::format(
      "simulation failed at t = {:.10g}: computing '{}' left its domain {}",
      t, name, kDomainExamples);
  if (lastGood < t)
    msg += fmt::format("; at t = {:.10g} it was inside", lastGood);
  std::string origin = m.output_origin && m.output_origin[output]
                           ? m.output_origin[output]
                           : "";
  if (!origin.empty())
    msg += "\n  in the equation at " + origin + sourceWithCaret(origin);
  msg += externalCodeMessage(takeModelicaError());
  // The integrator's unknowns it is computed from (all of them when few).
  if (ev.n() <= static_cast<int>(kMaxValuesListed)) {
    std::string values;
    for (int i = 0; i < ev.n(); ++i)
      values += fmt::format("{}'{}' = {:.10g}", i ? ", " : "", ev.varName(i),
                            y[i]);
    if (!values.empty())
      msg += "\n  values: " + values;
  }
  return msg + "\n  hint: '" + name +
         "' is computed at output times only; check the start values and "
         "parameters, the solution may really leave the domain here";
}

std::string describeSolverError(double t, const std::string &what) {
  return fmt::format("simulation failed at t = {:.10g}: {}\n  hint: the "
                     "solver could not be set up here; try other --rtol and "
                     "--atol values, and report the model if it persists",
                     t, what);
}

std::string describeFailure(const ModelEval &ev, const Integrator &integrator,
                            const StepStatus &status, double t) {
  FailureText text = failureText(status.failure);
  std::string msg = fmt::format("simulation failed at t = {:.10g}: {} ({})", t,
                                text.what, status.code);
  // The solver's own words say most about a failure we have no name for.
  if (status.failure == FailureKind::Other &&
      !integrator.solverMessage().empty())
    msg += fmt::format("\n  the solver says: {}", integrator.solverMessage());
  std::string worst = worstVariables(ev, integrator);
  if (!worst.empty())
    msg += "\n  largest local errors: " + worst;
  FailureKind k = status.failure;
  if ((k == FailureKind::Domain || k == FailureKind::Convergence ||
       k == FailureKind::StepCollapsed) &&
      integrator.lastDomainRow() >= 0)
    msg += describeDomainRow(ev, integrator.set(), integrator.lastDomainRow(),
                             integrator.lastDomainY(), t, nullptr);
  else if (k == FailureKind::LinearSetup || k == FailureKind::Convergence ||
           k == FailureKind::LinearSolve)
    for (int r : singularRows(ev, integrator, t))
      msg += describeDomainRow(ev, integrator.set(), r, integrator.y(), t,
                               integrator.yp());
  msg += fmt::format("\n  hint: {}", text.hint);
  // A system handed over as written whose index exceeds one (--method
  // raw) is the likeliest cause of any failure, whatever its symptom.
  if (ev.model().algebraic_error_test == 0)
    msg += "; the system is of index above one as written (--method raw): "
           "try --method dd";
  return msg;
}

std::string describeInitFailure(const ModelEval &ev,
                                const Integrator &integrator,
                                const StepStatus &status, double t) {
  if (integrator.lastDomainRow() >= 0)
    return describeInitDomainError(ev, integrator.set(),
                                   integrator.lastDomainRow(),
                                   integrator.lastDomainY(), t);
  return fmt::format("initialization failed at t = {:.10g}: no consistent "
                     "initial point found ({})\n  hint: check the start "
                     "values",
                     t, status.code);
}

} // namespace ldae::runtime
