// The callback status shared by IDA and CVODE (see Integrator.h). The
// choice between them is MakeIntegrator.cpp's, so that the method-neutral
// face knows neither.
#include "integrators/Integrator.h"

#include <cmath>

namespace ldae::runtime {

int Integrator::callbackStatus(CallbackData &d, int rc, const double *y) {
  if (rc > 0) {
    d.domainRow = rc - 1;
    d.domainY.assign(y, y + d.ev->n());
    return 1;
  }
  return rc < 0 ? -1 : 0;
}

bool Integrator::finite(const double *v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i]))
      return false;
  return true;
}

} // namespace ldae::runtime
