// The error weights of computed variables carried onto the states they are
// computed from (see ErrorWeights.h).
#include "integrators/ErrorWeights.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ldae::runtime {

namespace {

/// A computed variable is not asked to be more accurate than this many
/// units of round-off of the states it is computed from: y3 = 1 - y1 - y2
/// near 0 cannot be known better than y1 ~ 1 is stored, and a tolerance
/// below that made the solvers give up at once (CV_TOO_MUCH_ACC:
/// examples/robertson.lsd at atol 1e-20).
constexpr double kRoundoffUnits = 100;

} // namespace

ErrorWeights::ErrorWeights(const ModelEval &ev, double rtol, double atol)
    : ev_(ev), rtol_(rtol) {
  const ldae_model &m = ev.model();
  atol_.resize(m.n);
  for (int i = 0; i < m.n; ++i)
    atol_[i] = atol * (m.nominal ? m.nominal[i] : 1.0);
  if (m.n_tested > 0 && m.tested && m.tested_jacobian_csc &&
      m.tested_jac_colptr && m.tested_jac_rowind && m.tested_nominal) {
    n_ = m.n_tested;
    zAtol_.resize(n_);
    for (int j = 0; j < n_; ++j)
      zAtol_[j] = atol * m.tested_nominal[j];
    z_.resize(n_);
    scale_.resize(n_);
    jac_.resize(m.tested_jac_nnz);
  }
}

void ErrorWeights::own(const double *y, double *ewt) const {
  for (int i = 0; i < ev_.n(); ++i)
    ewt[i] = 1.0 / (rtol_ * std::fabs(y[i]) + atol_[i]);
}

void ErrorWeights::compute(double t, const double *y, const double *yp,
                           double *ewt) {
  own(y, ewt);
  if (n_ == 0)
    return;
  const ldae_model &m = ev_.model();
  const double *p = ev_.params();
  if (m.tested(t, y, yp, p, z_.data()) != 0 ||
      m.tested_jacobian_csc(t, y, yp, p, 0.0, jac_.data()) != 0)
    return;
  const int n = ev_.n();
  const int *colptr = m.tested_jac_colptr, *rowind = m.tested_jac_rowind;
  std::fill(scale_.begin(), scale_.end(), 0.0);
  // The floor of each tol_j: what the states' absolute tolerances and
  // round-off leave of z_j, sum_i |dz_j/dy_i| (atol_i + 100 u |y_i|).
  for (int i = 0; i < n; ++i) {
    double floor = atol_[i] + kRoundoffUnits * DBL_EPSILON * std::fabs(y[i]);
    for (int k = colptr[i]; k < colptr[i + 1]; ++k)
      scale_[rowind[k]] += std::fabs(jac_[k]) * floor;
  }
  // scale_ becomes 1 / tol_j.
  for (int j = 0; j < n_; ++j)
    scale_[j] =
        1.0 / std::max(rtol_ * std::fabs(z_[j]) + zAtol_[j], scale_[j]);
  for (int i = 0; i < n; ++i)
    for (int k = colptr[i]; k < colptr[i + 1]; ++k)
      ewt[i] = std::max(ewt[i], std::fabs(jac_[k]) * scale_[rowind[k]]);
}

} // namespace ldae::runtime
