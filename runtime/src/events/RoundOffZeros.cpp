// Values within round-off of zero (see RoundOffZeros.h).
#include "events/RoundOffZeros.h"

#include <cmath>

namespace ldae::runtime {

bool snapRoundOffZeros(const ModelEval &ev, std::vector<double> &y,
                       std::vector<double> &yp, const double *yFrom,
                       const double *ypFrom) {
  const ldae_model &m = ev.model();
  bool changed = false;
  auto snap = [&](double &v, double from, double nominal) {
    if (v != 0 && v != from && std::fabs(v) <= kRoundOffZero * nominal) {
      v = 0;
      changed = true;
    }
  };
  for (int i = 0; i < ev.n(); ++i) {
    double nominal = m.nominal ? m.nominal[i] : 1.0;
    if (i < int(y.size()))
      snap(y[i], yFrom[i], nominal);
    if (i < int(yp.size()))
      snap(yp[i], ypFrom[i], nominal);
  }
  return changed;
}

} // namespace ldae::runtime
