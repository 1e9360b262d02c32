// Evaluating a compiled model through its C ABI with the runtime's choice of
// parameters and state set: residuals, dense Jacobians (from the dense or
// the CSC function, or by difference quotients when the model gives
// neither), names and source locations for messages. The parameter vector
// every ABI function receives also carries the discrete state (ABI 6):
// p = [parameters | discrete values | their pre() values].
#pragma once

#include "ldae/model.h"
#include "numeric/SparseLu.h"

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace ldae::runtime {

using numeric::CscMatrix;
using numeric::SparseLu;

class ModelEval {
public:
  /// `params`: the n_params parameter values (the discrete values start
  /// at discrete_start, current and pre alike), or all of p.
  ModelEval(const ldae_model &m, std::vector<double> params);

  const ldae_model &model() const { return m_; }
  /// p as the ABI functions take it (n_params + 2 * n_discrete values).
  const double *params() const { return p_.data(); }
  int nDiscrete() const { return m_.n_discrete; }
  /// The current discrete values (n_discrete) and their pre() values.
  double *discrete() { return p_.data() + m_.n_params; }
  const double *discrete() const { return p_.data() + m_.n_params; }
  double *pre() { return discrete() + m_.n_discrete; }
  const double *pre() const { return discrete() + m_.n_discrete; }
  /// The discrete value's name ("d[3]" when the model has none).
  std::string discreteName(int k) const;
  /// The name for a message: a variable quoted ('flying'), a relation,
  /// whose text quotes its own names, in parentheses.
  std::string quotedDiscreteName(int k) const;
  /// Index of the parameter called `name`, or -1.
  int paramIndex(const char *name) const;
  /// Changes a parameter for every later evaluation (the homotopy
  /// continuation of the initialization).
  void setParam(int i, double v) { p_[i] = v; }
  int n() const { return m_.n; }
  const ldae_state_set &set(int k) const { return m_.state_sets[k]; }

  /// r = F_k(t, y, y'); returns the ABI status (0 ok, >0 domain error row+1).
  int residual(int k, double t, const double *y, const double *yp,
               double *r) const {
    return set(k).residual(t, y, yp, p_.data(), r);
  }
  /// J = dF_k/dy + cj dF_k/dy' as a dense matrix.
  int jacobian(int k, double t, const double *y, const double *yp, double cj,
               Eigen::MatrixXd &J) const;
  /// dF/dy (cj = 0) and E = dF/dy' (from cj = 1 minus cj = 0).
  int jacobianParts(int k, double t, const double *y, const double *yp,
                    Eigen::MatrixXd &Fy, Eigen::MatrixXd &E) const;
  /// J = dF_k/dy + cj dF_k/dy' in the set's CSC pattern (from the dense
  /// Jacobian or difference quotients, keeping the nonzeros, when the set
  /// has no CSC function: only hand-written models).
  int jacobianCsc(int k, double t, const double *y, const double *yp, double cj,
                  CscMatrix &J) const;
  /// jacobianParts in one shared CSC pattern, O(nnz) for a CSC model.
  int jacobianPartsCsc(int k, double t, const double *y, const double *yp,
                       CscMatrix &Fy, CscMatrix &E) const;

  /// g = G(t, y, y'), the initial equations (n_init values).
  int initResidual(double t, const double *y, const double *yp,
                   double *g) const {
    return m_.init_residual(t, y, yp, p_.data(), g);
  }
  /// dG/dy and dG/dy' as dense n_init x n matrices (from the dense
  /// function, or scattered from the CSC one above the threshold).
  int initJacobian(double t, const double *y, const double *yp,
                   Eigen::MatrixXd &Gy, Eigen::MatrixXd &Gyp) const;
  /// Whether the model gives the initial equations' CSC Jacobian.
  bool hasInitJacobianCsc() const {
    return m_.n_init == 0 ||
           (m_.init_jacobian_csc && m_.init_jac_colptr && m_.init_jac_rowind);
  }
  /// dG/dy and dG/dy' values in the model's init CSC pattern.
  int initJacobianCsc(double t, const double *y, const double *yp,
                      std::vector<double> &gy, std::vector<double> &gyp) const;

  /// dF/dy and dF/dy' of the model as written (the geometric methods'
  /// ldae_model::written_residual), dense n_written x n; 0 rows without.
  int writtenJacobian(double t, const double *y, const double *yp,
                      Eigen::MatrixXd &Fy, Eigen::MatrixXd &E) const;

  /// The unknown's name ("y[3]" when the model has none).
  std::string varName(int i) const;
  /// "file:line" of the equation of residual row `row`, or "" if unknown.
  std::string origin(int row) const;
  /// "'name' (file:line)"-style description of a residual row.
  std::string describeRow(int row) const;

private:
  const ldae_model &m_;
  std::vector<double> p_;
};

} // namespace ldae::runtime
