// Conditioning of state sets' pivot matrices and the switching rule (see
// StateSelection.h).
#include "model/StateSelection.h"
#include "numeric/Rank.h"
#include "numeric/StatePivot.h"

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
    numeric::SingularRange sv = numeric::singularRangeByGram(M);
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

namespace {

/// The names of the candidates whose isDummy is `which` (0: the states),
/// joined.
std::string namesOf(const ldae_dynamic_set &s, const std::vector<char> &isDummy,
                    char which) {
  std::string out;
  for (int j = 0; j < s.candidates; ++j)
    if (isDummy[j] == which)
      out += (out.empty() ? "" : ", ") + std::string(s.names[j]);
  return out;
}

} // namespace

std::vector<DynamicSwitch> reselectDynamicSets(ModelEval &ev, double t,
                                               double *y, double *yp) {
  const ldae_model &m = ev.model();
  std::vector<DynamicSwitch> out;
  for (int d = 0; d < m.n_dynamic_sets; ++d) {
    const ldae_dynamic_set &s = m.dynamic_sets[d];
    const int nc = s.candidates, ns = s.forced + s.candidates - s.rows;
    Eigen::MatrixXd J(s.rows, s.forced + nc);
    if (s.jacobian(t, y, yp, ev.params(), J.data()) != 0 || !J.allFinite())
      continue;
    // The current dummies: the candidates no row of A selects.
    const double *A = ev.params() + s.param;
    std::vector<int> now;
    std::vector<char> wasDummy(nc, 1);
    for (int j = 0; j < nc; ++j) {
      for (int k = 0; k < ns; ++k)
        if (A[k + ns * j] != 0)
          wasDummy[j] = 0;
      if (wasDummy[j])
        now.push_back(j);
    }
    Eigen::MatrixXd S = numeric::reduceForced(J, s.forced);
    std::vector<int> best = numeric::pivotDummies(S);
    if (best.empty() || best == now)
      continue;
    const double smax = numeric::singularRangeByGram(S).max;
    std::vector<double> cond{numeric::dummyCondition(S, now, smax),
                             numeric::dummyCondition(S, best, smax)};
    if (chooseStateSet(cond, 0) != 1)
      continue;
    std::vector<char> isDummy(nc, 0);
    for (int j : best)
      isDummy[j] = 1;
    std::vector<double> v(2 * size_t(nc));
    if (s.values(t, y, yp, ev.params(), v.data()) != 0)
      continue;
    out.push_back(
        {d, namesOf(s, wasDummy, 0), namesOf(s, isDummy, 0), cond[0], cond[1]});
    int k = 0;
    for (int j = 0; j < nc; ++j) {
      for (int r = 0; r < ns; ++r)
        ev.setParam(s.param + r + ns * j, 0.0);
      if (isDummy[j])
        continue;
      ev.setParam(s.param + k + ns * j, 1.0);
      y[s.state_slots[k]] = v[j];
      yp[s.state_slots[k]] = v[nc + j];
      ++k;
    }
  }
  return out;
}

} // namespace ldae::runtime
