// Conditioning of state sets' pivot matrices and the switching rule (see
// StateSelection.h).
#include "StateSelection.h"
#include "numeric/Rank.h"

#include <cmath>
#include <limits>

namespace ldae::runtime {

std::vector<double> pivotConditions(const ModelEval &ev, double t,
                                    const double *y, const double *yp) {
  const ldae_model &m = ev.model();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> smin(m.n_state_sets, 0.0), cond(m.n_state_sets, 1.0);
  double smax = 0;
  for (int k = 0; k < m.n_state_sets; ++k) {
    const ldae_state_set &s = m.state_sets[k];
    if (s.pivot_size <= 0 || !s.pivot)
      continue;
    Eigen::MatrixXd M(s.pivot_size, s.pivot_size);
    if (s.pivot(t, y, yp, ev.params(), M.data()) != 0 || !M.allFinite()) {
      smin[k] = -1; // cannot be evaluated: never prefer it
      continue;
    }
    numeric::SingularRange sv = numeric::singularRange(M);
    smax = std::max(smax, sv.max);
    smin[k] = sv.min;
  }
  for (int k = 0; k < m.n_state_sets; ++k) {
    const ldae_state_set &s = m.state_sets[k];
    if (s.pivot_size <= 0 || !s.pivot)
      continue;
    cond[k] = smin[k] > 0 && smax > 0 ? smax / smin[k] : inf;
  }
  return cond;
}

int chooseStateSet(const std::vector<double> &cond, int current) {
  if (cond.empty() || !(cond[current] > kSwitchThreshold))
    return current;
  int best = current;
  for (int k = 0; k < (int)cond.size(); ++k)
    if (cond[k] < cond[best])
      best = k;
  if (best != current && cond[best] * kHysteresis < cond[current])
    return best;
  return current;
}

} // namespace ldae::runtime
