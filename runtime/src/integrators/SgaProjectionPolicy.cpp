// The SGA's projection policy under CVODE (see SgaProjectionPolicy.h).
#include "integrators/SgaProjectionPolicy.h"
#include "init/JumpRule.h"

#include <algorithm>
#include <cmath>

namespace ldae::runtime {

namespace {

/// CVODE 6.4 projects only BDF steps. Adams (sga) integrates instead the
/// stabilized field f(y) - gamma D (Jc D)^+ c(y), equal to f on P_f, whose
/// drift decays at the rate gamma instead of growing (the pendulum's grows
/// like t^3 through the lambda' row): gamma = kStabilization times
/// ||df/dy||_inf at the start (capped: kRateCap), a bound on the rates of
/// the linearization.
/// Larger makes Adams' steps stability-bound at loose tolerances (at 4 x
/// this, the pendulum took more steps at rtol 1e-6 than at 1e-10).
constexpr double kStabilization = 0.5;
/// The norm bounds the rates only in units that are commensurate; it is
/// capped at this many times the spectral radius, which no choice of
/// units changes. Andrews' squeezer's norm, 4e10, is d v'/d m11 (v' =
/// M^-1 (f - G^T lambda) against an inertia entry of 1e-6), not a rate
/// (its spectral radius at the start is 466): gamma = 2e10 held Adams at
/// 4e-11 s steps (100,000 of them before t = 4e-6).
/// The radius is the largest seen, at the start and at every stiffness
/// check (StiffnessDetector, every 25 Adams steps) after it: at rest it says
/// little of the motion (the pendulum released near horizontal, theta0 = 1.56,
/// has a small one, and gamma capped by it was 3.1e-5 off at rtol 1e-9 instead
/// of 7e-6). Raising gamma during the run changes the field only off P_f, by
/// the drift (1e-14) times the change. It costs Andrews steps (1780, 1648, 2386
/// at rtol 1e-6, 1e-8, 1e-10 against 641, 880, 1806 on the start's radius), not
/// accuracy (q 1.9e-7 and 1.7e-11 off its reference at 1e-8 and 1e-10); 6 x the
/// largest radius took 440, 760, 1740 steps but was 4.9e-7 and 3.0e-9 off, and
/// moved the pendulum's gamma below the norm's 16 (its error erratic in gamma:
/// docs/runtime.md).
constexpr double kRateCap = 40;
/// And it restarts from the projected point when the drift's correction
/// exceeds this many local error tolerances (WRMS norm in CVODE's error
/// weights): a restart resets Adams' order and costs accuracy (with 684
/// restarts in 100 s the pendulum was 1.7e-6 off at rtol 1e-10, 1e-7 with
/// the stabilization and none), so only as a safety net.
constexpr double kAdamsDriftRestart = 10.0;

} // namespace

SgaProjectionPolicy::SgaProjectionPolicy(const ModelEval &ev)
    : ev_(ev), projection_(ev) {}

std::vector<int> SgaProjectionPolicy::fixedUnknowns() const {
  std::vector<int> fixed;
  const int *f = ev_.model().fixed;
  for (int i = 0; f && i < ev_.n(); ++i)
    if (f[i])
      fixed.push_back(i);
  return fixed;
}

bool SgaProjectionPolicy::jumpOntoConstraints(double t, double *y,
                                              const double *yp,
                                              const std::vector<int> &held,
                                              const Field &field) {
  const int n = ev_.n();
  if (ev_.model().n_written <= 0)
    return false;
  // The pencil's F reads y' through E(y) y' terms: the field's value at
  // the point where the caller has none (the start).
  std::vector<double> f(n, 0.0);
  if (!yp) {
    if (field(t, y, f.data()) != 0)
      std::fill(f.begin(), f.end(), 0.0);
    yp = f.data();
  }
  const Eigen::MatrixXd T = writtenJumpBasis(ev_, t, y, yp, held);
  if (T.cols() == 0)
    return false;
  std::vector<double> along(y, y + n);
  if (projection_.projectAlong(t, along.data(), T) != 0)
    return false;
  std::copy(along.begin(), along.end(), y);
  return true;
}

bool SgaProjectionPolicy::stabilizeAt(ImplicitOde &field, double t,
                                      const double *y) {
  // The drift of an Adams run decays at this rate instead of growing
  // (see kStabilization).
  Eigen::MatrixXd J;
  Eigen::VectorXcd lambda;
  if (!field.linearization(t, y, J, lambda))
    return false;
  rateNorm_ = J.cwiseAbs().rowwise().sum().maxCoeff();
  radiusMax_ = 0;
  raiseStabilization(lambda);
  return true;
}

void SgaProjectionPolicy::raiseStabilization(const Eigen::VectorXcd &lambda) {
  if (lambda.size() > 0)
    radiusMax_ = std::max(radiusMax_, lambda.cwiseAbs().maxCoeff());
  rate_ = kStabilization * std::min(rateNorm_, kRateCap * radiusMax_);
}

SgaProjectionPolicy::Drift
SgaProjectionPolicy::checkDrift(double t, const double *y,
                                const Weights &weights,
                                std::vector<double> &restart) {
  // CVODE projects BDF steps only: Adams restarts from the projected
  // point once the drift's correction (one Gauss-Newton step: its size
  // is all that matters here) exceeds kAdamsDriftRestart tolerances.
  int n = ev_.n();
  std::vector<double> dy(n);
  const double *w = nullptr;
  if (projection_.correction(t, y, dy.data()) != 0 || !(w = weights()))
    return Drift::Failed;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    sum += (dy[i] * w[i]) * (dy[i] * w[i]);
  if (std::sqrt(sum / n) > kAdamsDriftRestart) {
    // Restarted at the next step: output times within this one are
    // still interpolated from its polynomial.
    std::vector<double> yq(y, y + n);
    if (projection_.project(t, yq.data(), false) != 0)
      return Drift::Failed;
    restart = std::move(yq);
    return Drift::Restart;
  }
  return Drift::Within;
}

} // namespace ldae::runtime
