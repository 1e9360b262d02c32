// How CVODE keeps a linearly implicit model on its constraints (`--method
// sga|ode`, ldae_model::project_constraints): where a start and a restart
// after an event land (the start's rule, seed 002's jump along T(E, F) of
// the model as written), and, for Adams, which CVODE 6.4 does not project,
// the rate of the stabilized field and the drift at which a restart from the
// projected point is due. ConstraintProjection does the projecting;
// CvodeIntegrator decides when CVODE calls it.
#pragma once

#include "integrators/ConstraintProjection.h"
#include "integrators/ImplicitOde.h"
#include "model/ModelEval.h"

#include <Eigen/Dense>
#include <functional>
#include <vector>

namespace ldae::runtime {

class SgaProjectionPolicy {
public:
  /// The field CVODE integrates: f(t, y) into f, the ABI status.
  using Field = std::function<int(double t, const double *y, double *f)>;
  /// The error weights of CVODE's local error test (null: not available).
  using Weights = std::function<const double *()>;

  explicit SgaProjectionPolicy(const ModelEval &ev);

  ConstraintProjection &projection() { return projection_; }
  const ConstraintProjection &projection() const { return projection_; }
  /// Whether the model has constraints to keep.
  bool active() const { return projection_.active(); }

  /// The unknowns with a fixed start value.
  std::vector<int> fixedUnknowns() const;
  /// Seed 002's rule on the model as written (ldae_model::written_*): y
  /// moves along T(E, F) at (t, y, y') onto every constraint; the unknowns
  /// `held` keep their values (the fixed start values at the start, the
  /// reinit targets after an event); y' null: `field`'s. False, y
  /// untouched, without the pencil or where the constraints cannot be met
  /// along T (the nearest point then decides).
  bool jumpOntoConstraints(double t, double *y, const double *yp,
                           const std::vector<int> &held, const Field &field);

  /// The Adams stabilization's rate from the linearization at a start
  /// (t, y): false, the rate unchanged, where it cannot be computed.
  bool stabilizeAt(ImplicitOde &field, double t, const double *y);
  /// Raises the rate to the spectral radius of `lambda` where that is the
  /// largest seen (kRateCap).
  void raiseStabilization(const Eigen::VectorXcd &lambda);
  /// gamma of the stabilized field f(y) - gamma D (Jc D)^+ c(y).
  double stabilization() const { return rate_; }

  enum class Drift { Within, Restart, Failed };
  /// After an Adams step to (t, y): Restart with `restart` the projected
  /// point when the drift's correction exceeds kAdamsDriftRestart
  /// tolerances in `weights`; Failed when the correction, the weights or
  /// the projection cannot be had.
  Drift checkDrift(double t, const double *y, const Weights &weights,
                   std::vector<double> &restart);

private:
  const ModelEval &ev_;
  ConstraintProjection projection_;
  /// The stabilization rate's bounds (kRateCap): ||df/dy|| at the start
  /// and the largest spectral radius seen.
  double rateNorm_ = 0, radiusMax_ = 0;
  double rate_ = 0;
};

} // namespace ldae::runtime
