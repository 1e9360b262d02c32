// The error weights of the integrators' local error test when the causal
// form computes unknowns of the index-1 system outside the integrator
// (ldae_model::tested). Left alone, such a variable z = g(y) has the error
// of the states it is computed from, measured against their tolerances, not
// its own: Robertson's y3 = 1 - y1 - y2 inherits y1's relative error as an
// absolute one, 40x its own bound. So each state's weight becomes the
// largest that it or any variable computed from it demands,
//   w_i = max(1 / (rtol |y_i| + atol_i), max_j |dz_j/dy_i| / tol_j),
// tol_j = rtol |z_j| + atol nominal_j, floored at what round-off leaves of
// z_j (docs/runtime.md, "The error test"). IDA and CVODE call this at every
// step through IDAWFtolerances / CVodeWFtolerances.
#pragma once

#include "model/ModelEval.h"

#include <vector>

namespace ldae::runtime {

class ErrorWeights {
public:
  /// `atol` is scaled by each unknown's and computed variable's nominal
  /// value.
  ErrorWeights(const ModelEval &ev, double rtol, double atol);

  /// Whether the model computes variables the weights must account for.
  bool propagates() const { return n_ > 0; }
  double rtol() const { return rtol_; }
  /// The unknowns' absolute tolerances.
  const std::vector<double> &atol() const { return atol_; }

  /// ewt (n values) at (t, y, y'). Falls back to the states' own weights
  /// where the model cannot evaluate z or dz/dy there (a trial point out of
  /// a domain): the step itself will fail or be retried.
  void compute(double t, const double *y, const double *yp, double *ewt);

private:
  /// The states' own weights.
  void own(const double *y, double *ewt) const;

  const ModelEval &ev_;
  double rtol_;
  std::vector<double> atol_;
  int n_ = 0; // tested variables (0: none, or the model gives no function)
  std::vector<double> zAtol_; // their absolute tolerances
  std::vector<double> z_, jac_, scale_;
};

} // namespace ldae::runtime
