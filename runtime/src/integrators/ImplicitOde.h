// The vector field of a linearly implicit model (ldae_model::n_ode = n,
// `--method sga|ode`): every row is A(t, y) y' - alpha(t, y), so
// F(t, y, y') = E(t, y) y' + F(t, y, 0) with E = dF/dy', and
//   f(t, y)  solves  E(t, y) f = -F(t, y, 0),
//   df/dy  = -E^-1 dF/dy(t, y, f)
// (differentiate E f + F(t, y, 0) = 0: the y-derivative of E's entries
// times f is dF/dy's y'-dependent part at y' = f, so this is exact for
// rows linear in y'). CVODE integrates f with the model's own residual and
// Jacobian functions. E is equilibrated (rows, then columns) before it is
// factored and its condition judged: a model's units must not make it
// singular.
#pragma once

#include "model/ModelEval.h"

#include <Eigen/Dense>
#include <vector>

namespace ldae::runtime {

class ImplicitOde {
public:
  explicit ImplicitOde(const ModelEval &ev);

  /// f(t, y) into `f`. The ABI status (0 ok, > 0 a domain error in row
  /// rc - 1, < 0 fatal), or kSingular when dF/dy' is singular at (t, y).
  int rhs(double t, const double *y, double *f);
  /// df/dy at (t, y) with f = f(t, y), dense column-major into `J` (n x n).
  int jacobian(double t, const double *y, const double *f, double *J);
  /// df/dy at (t, y) into `J` and its eigenvalues into `lambda` (false:
  /// not computed), for the Adams stabilization and the stiffness test.
  bool linearization(double t, const double *y, Eigen::MatrixXd &J,
                     Eigen::VectorXcd &lambda);

  /// rhs/jacobian's status for a singular dF/dy' (a recoverable failure:
  /// off the manifold the rows may lose rank; smaller steps stay nearer).
  static constexpr int kSingular = 1 << 30;

private:
  /// Factors E(t, y) unless it already holds that point's factors.
  int factor(double t, const double *y);

  const ModelEval &ev_;
  int n_;
  Eigen::MatrixXd J0_, Jc_;
  /// E's equilibration: lu_ factors diag(rowScale_) E diag(colScale_).
  Eigen::VectorXd rowScale_, colScale_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  std::vector<double> zeros_, r_, yAt_;
  double tAt_ = 0;
  bool factored_ = false;
};

} // namespace ldae::runtime
