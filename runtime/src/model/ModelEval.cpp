// Residual and Jacobian evaluation through the C ABI (see ModelEval.h).
#include "model/ModelEval.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fmt/format.h>

namespace ldae::runtime {

ModelEval::ModelEval(const ldae_model &m, std::vector<double> params)
    : m_(m), p_(std::move(params)) {
  int nd = std::max(m.n_discrete, 0);
  if (p_.size() == size_t(std::max(m.n_params, 0)) && nd > 0) {
    p_.insert(p_.end(), m.discrete_start, m.discrete_start + nd);
    p_.insert(p_.end(), m.discrete_start, m.discrete_start + nd);
  }
  // The selection matrices of dynamic state selection (ABI 8) follow.
  const size_t withSelection =
      size_t(std::max(m.n_params, 0)) + 2 * nd + std::max(m.n_selection, 0);
  if (m.n_selection > 0 && p_.size() < withSelection) {
    p_.resize(withSelection, 0.0);
    for (int d = 0; d < m.n_dynamic_sets; ++d) {
      const ldae_dynamic_set &s = m.dynamic_sets[d];
      int size = (s.forced + s.candidates - s.rows) * s.candidates;
      std::copy(s.start, s.start + size, p_.begin() + s.param);
    }
  }
}

std::string ModelEval::discreteName(int k) const {
  if (m_.discrete_names && m_.discrete_names[k])
    return m_.discrete_names[k];
  return fmt::format("d[{}]", k);
}

std::string ModelEval::quotedDiscreteName(int k) const {
  if (m_.discrete_kind && m_.discrete_kind[k] == LDAE_DISCRETE_RELATION)
    return "(" + discreteName(k) + ")";
  return "'" + discreteName(k) + "'";
}

int ModelEval::jacobian(int k, double t, const double *y, const double *yp,
                        double cj, Eigen::MatrixXd &J) const {
  const ldae_state_set &s = set(k);
  int n = m_.n;
  J.setZero(n, n);
  if (s.jacobian_dense)
    return s.jacobian_dense(t, y, yp, p_.data(), cj, J.data());
  if (s.jacobian_csc) {
    std::vector<double> vals(s.jac_nnz);
    if (int rc = s.jacobian_csc(t, y, yp, p_.data(), cj, vals.data()))
      return rc;
    for (int c = 0; c < n; ++c)
      for (int q = s.jac_colptr[c]; q < s.jac_colptr[c + 1]; ++q)
        J(s.jac_rowind[q], c) = vals[q];
    return 0;
  }
  // Central differences, one column at a time, perturbing y and y'
  // together the way the iteration matrix combines them (central: the
  // initialization builds hidden constraints from these coefficients).
  std::vector<double> r0(n), r1(n), yy(y, y + n), yyp(yp, yp + n);
  for (int c = 0; c < n; ++c) {
    double scale = std::max(
        {std::fabs(y[c]), std::fabs(yp[c]), m_.nominal ? m_.nominal[c] : 1.0});
    double h = 6e-6 * scale;
    yy[c] = y[c] + h;
    yyp[c] = yp[c] + cj * h;
    int rc = residual(k, t, yy.data(), yyp.data(), r1.data());
    yy[c] = y[c] - h;
    yyp[c] = yp[c] - cj * h;
    if (rc == 0)
      rc = residual(k, t, yy.data(), yyp.data(), r0.data());
    yy[c] = y[c];
    yyp[c] = yp[c];
    if (rc)
      return rc;
    for (int r = 0; r < n; ++r)
      J(r, c) = (r1[r] - r0[r]) / (2 * h);
  }
  return 0;
}

int ModelEval::jacobianParts(int k, double t, const double *y, const double *yp,
                             Eigen::MatrixXd &Fy, Eigen::MatrixXd &E) const {
  if (int rc = jacobian(k, t, y, yp, 0.0, Fy))
    return rc;
  if (int rc = jacobian(k, t, y, yp, 1.0, E))
    return rc;
  E -= Fy;
  return 0;
}

namespace {
/// The nonzeros of dense matrices (the union of their patterns) as CSC
/// matrices with one pattern.
void denseToCsc(const std::vector<const Eigen::MatrixXd *> &dense,
                const std::vector<CscMatrix *> &out) {
  int n = int(dense[0]->cols());
  for (CscMatrix *c : out) {
    c->n = n;
    c->colptr.assign(1, 0);
    c->rowind.clear();
    c->values.clear();
  }
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) {
      bool any = false;
      for (const Eigen::MatrixXd *d : dense)
        any |= (*d)(r, c) != 0;
      if (!any)
        continue;
      for (size_t i = 0; i < out.size(); ++i) {
        out[i]->rowind.push_back(r);
        out[i]->values.push_back((*dense[i])(r, c));
      }
    }
    for (CscMatrix *m : out)
      m->colptr.push_back(int(m->rowind.size()));
  }
}

void setPattern(const ldae_state_set &s, int n, CscMatrix &J) {
  J.n = n;
  J.colptr.assign(s.jac_colptr, s.jac_colptr + n + 1);
  J.rowind.assign(s.jac_rowind, s.jac_rowind + s.jac_nnz);
  J.values.assign(s.jac_nnz, 0.0);
}
} // namespace

int ModelEval::jacobianCsc(int k, double t, const double *y, const double *yp,
                           double cj, CscMatrix &J) const {
  const ldae_state_set &s = set(k);
  if (s.jacobian_csc && s.jac_colptr) {
    setPattern(s, m_.n, J);
    return s.jacobian_csc(t, y, yp, p_.data(), cj, J.values.data());
  }
  Eigen::MatrixXd D;
  if (int rc = jacobian(k, t, y, yp, cj, D))
    return rc;
  denseToCsc({&D}, {&J});
  return 0;
}

int ModelEval::jacobianPartsCsc(int k, double t, const double *y,
                                const double *yp, CscMatrix &Fy,
                                CscMatrix &E) const {
  const ldae_state_set &s = set(k);
  if (!(s.jacobian_csc && s.jac_colptr)) {
    Eigen::MatrixXd DFy, DE;
    if (int rc = jacobianParts(k, t, y, yp, DFy, DE))
      return rc;
    denseToCsc({&DFy, &DE}, {&Fy, &E});
    return 0;
  }
  if (int rc = jacobianCsc(k, t, y, yp, 0.0, Fy))
    return rc;
  if (int rc = jacobianCsc(k, t, y, yp, 1.0, E))
    return rc;
  for (size_t q = 0; q < E.values.size(); ++q)
    E.values[q] -= Fy.values[q];
  return 0;
}

int ModelEval::initJacobianCsc(double t, const double *y, const double *yp,
                               std::vector<double> &gy,
                               std::vector<double> &gyp) const {
  gy.assign(m_.init_jac_nnz, 0.0);
  gyp.assign(m_.init_jac_nnz, 0.0);
  if (m_.n_init == 0)
    return 0;
  return m_.init_jacobian_csc(t, y, yp, p_.data(), gy.data(), gyp.data());
}

int ModelEval::initJacobian(double t, const double *y, const double *yp,
                            Eigen::MatrixXd &Gy, Eigen::MatrixXd &Gyp) const {
  int ni = m_.n_init, n = m_.n;
  Gy.setZero(ni, n);
  Gyp.setZero(ni, n);
  if (ni == 0)
    return 0;
  if (m_.init_jacobian)
    return m_.init_jacobian(t, y, yp, p_.data(), Gy.data(), Gyp.data());
  std::vector<double> gy, gyp;
  if (int rc = initJacobianCsc(t, y, yp, gy, gyp))
    return rc;
  for (int c = 0; c < n; ++c)
    for (int q = m_.init_jac_colptr[c]; q < m_.init_jac_colptr[c + 1]; ++q) {
      Gy(m_.init_jac_rowind[q], c) = gy[q];
      Gyp(m_.init_jac_rowind[q], c) = gyp[q];
    }
  return 0;
}

int ModelEval::writtenJacobian(double t, const double *y, const double *yp,
                               Eigen::MatrixXd &Fy, Eigen::MatrixXd &E) const {
  const int rows = m_.written_jacobian ? m_.n_written : 0;
  Fy.setZero(rows, m_.n);
  E.setZero(rows, m_.n);
  if (rows == 0)
    return 0;
  return m_.written_jacobian(t, y, yp, p_.data(), Fy.data(), E.data());
}

int ModelEval::paramIndex(const char *name) const {
  for (int i = 0; i < m_.n_params; ++i)
    if (m_.param_names && m_.param_names[i] &&
        std::strcmp(m_.param_names[i], name) == 0)
      return i;
  return -1;
}

std::string ModelEval::varName(int i) const {
  if (m_.var_names && m_.var_names[i])
    return m_.var_names[i];
  return fmt::format("y[{}]", i);
}

std::string ModelEval::origin(int row) const {
  if (row < 0 || row >= m_.n || !m_.residual_origin || !m_.residual_origin[row])
    return "";
  return m_.residual_origin[row];
}

std::string ModelEval::describeRow(int row) const {
  std::string o = origin(row);
  if (o.empty())
    return fmt::format("equation {}", row + 1);
  return fmt::format("equation {} at {}", row + 1, o);
}

} // namespace ldae::runtime
