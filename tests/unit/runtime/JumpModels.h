// Hand-written reduced models with the jump rule's tables (ldae_model
// dummy_of / original_row), as dummy derivatives would reduce them, for the
// initialization and re-initialization along T of the model as written:
//  - twoCapacitors(): C1 der(v1) = -i, C2 der(v2) = i, v1 = v2, der(v2) a
//    dummy; the charge C1 v1 + C2 v2 is what the jump conserves.
//  - dummyPendulum(): x' = u, y' = v, u' = -lam x, v' = -lam y - g,
//    x^2 + y^2 = 1 with states x, u; der(y), der(v) dummies; the
//    differentiated constraints as rows that are not equations as written.
//  - inductorCutset(): a series R-L1-L2-C loop (the node between the
//    inductors is a cutset of inductors): the flux L1 i1 + L2 i2 is what
//    the jump conserves; der(i2) a dummy.
// Each has an exact dense Jacobian: the jump directions are computed from
// it, and difference quotients would cost the 1e-12 the tests ask for.
#pragma once

#include "HandModels.h"

namespace jumpmodels {

/// The per-set table pointers of a one-set model.
struct Tables {
  const int *dummy[1];
  const int *original[1];
  void attach(ldae_model &m) {
    m.dummy_of = dummy;
    m.original_row = original;
  }
};

/// What differs between the models below (arrays in static storage).
struct Spec {
  const char *name;
  int n;
  const char *const *names;
  const double *y0;
  const int *diff;
  ldae_residual_fn res;
  ldae_jacobian_dense_fn jac;
  int nParams;
  const char *const *paramNames;
  const double *params;
};

/// One state set, nominal values 1, nothing fixed, start derivatives 0.
inline ldae_model build(const Spec &s, ldae_state_set &set, Tables &tables) {
  static const double zeros[8] = {}, ones[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  static const int none[8] = {};
  set = ldae_state_set{};
  set.is_differential = s.diff;
  set.residual = s.res;
  set.jacobian_dense = s.jac;
  ldae_model m = handmodels::makeModel(s.name, s.n, s.names, s.y0, zeros,
                                       ones, none, &set);
  m.n_params = s.nParams;
  m.param_names = s.paramNames;
  m.param_values = s.params;
  tables.attach(m);
  return m;
}

// ---- Two capacitors ---------------------------------------------------
// Unknowns v1, v2, i, der(v2); p = {C1, C2}.
namespace caps_detail {
enum { V1, V2, I, DV2 };
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  r[0] = p[0] * yp[V1] + y[I];
  r[1] = p[1] * y[DV2] - y[I];
  r[2] = y[V1] - y[V2];
  r[3] = yp[V1] - y[DV2]; // der(v1 = v2): made by index reduction
  return 0;
}
inline int jac(double, const double *, const double *, const double *p,
               double cj, double *J) {
  auto at = [J](int r, int c) -> double & { return J[r + 4 * c]; };
  for (int k = 0; k < 16; ++k)
    J[k] = 0;
  at(0, V1) = p[0] * cj;
  at(0, I) = 1;
  at(1, DV2) = p[1];
  at(1, I) = -1;
  at(2, V1) = 1;
  at(2, V2) = -1;
  at(3, V1) = cj;
  at(3, DV2) = -1;
  return 0;
}
} // namespace caps_detail

inline ldae_model twoCapacitors(double C1, double C2, double v1, double v2) {
  using namespace caps_detail;
  static const char *names[] = {"v1", "v2", "i", "der(v2)"};
  static double y0[4], params[2];
  static const int diff[] = {1, 0, 0, 0};
  static const int dummy[] = {-1, -1, -1, V2}, original[] = {1, 1, 1, 0};
  static const char *pnames[] = {"C1", "C2"};
  static ldae_state_set set{};
  static Tables tables{{dummy}, {original}};
  y0[V1] = v1;
  y0[V2] = v2;
  y0[I] = y0[DV2] = 0;
  params[0] = C1;
  params[1] = C2;
  return build({"TwoCapacitors", 4, names, y0, diff, res, jac, 2, pnames,
                params},
               set, tables);
}

// ---- Pendulum with its dummy derivatives --------------------------------
// Unknowns x, y, u, v, lam, der(y), der(v); p = {g}.
namespace pend_detail {
enum { X, Y, U, V, LAM, DY, DV };
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  r[0] = yp[X] - y[U];
  r[1] = y[DY] - y[V];
  r[2] = yp[U] + y[LAM] * y[X];
  r[3] = y[DV] + y[LAM] * y[Y] + p[0];
  r[4] = y[X] * y[X] + y[Y] * y[Y] - 1;
  // The constraint differentiated once and twice (index reduction).
  r[5] = y[X] * yp[X] + y[Y] * y[DY];
  r[6] = yp[X] * yp[X] + y[X] * yp[U] + y[DY] * y[DY] + y[Y] * y[DV];
  return 0;
}
inline int jac(double, const double *y, const double *yp, const double *,
               double cj, double *J) {
  auto at = [J](int r, int c) -> double & { return J[r + 7 * c]; };
  for (int k = 0; k < 49; ++k)
    J[k] = 0;
  at(0, X) = cj;
  at(0, U) = -1;
  at(1, DY) = 1;
  at(1, V) = -1;
  at(2, U) = cj;
  at(2, LAM) = y[X];
  at(2, X) = y[LAM];
  at(3, DV) = 1;
  at(3, LAM) = y[Y];
  at(3, Y) = y[LAM];
  at(4, X) = 2 * y[X];
  at(4, Y) = 2 * y[Y];
  at(5, X) = yp[X] + cj * y[X];
  at(5, Y) = y[DY];
  at(5, DY) = y[Y];
  at(6, X) = yp[U] + cj * 2 * yp[X];
  at(6, U) = cj * y[X];
  at(6, DY) = 2 * y[DY];
  at(6, Y) = y[DV];
  at(6, DV) = y[Y];
  return 0;
}
} // namespace pend_detail

/// At angle theta from the downward vertical (on the circle), velocity
/// (u0, v0).
inline ldae_model dummyPendulum(double theta, double u0, double v0) {
  using namespace pend_detail;
  static const char *names[] = {"x", "y", "u", "v", "lam", "der(y)", "der(v)"};
  static double y0[7];
  static const double params[] = {9.81};
  static const char *pnames[] = {"g"};
  static const int diff[] = {1, 0, 1, 0, 0, 0, 0};
  static const int dummy[] = {-1, -1, -1, -1, -1, Y, V};
  static const int original[] = {1, 1, 1, 1, 1, 0, 0};
  static ldae_state_set set{};
  static Tables tables{{dummy}, {original}};
  y0[X] = std::sin(theta);
  y0[Y] = -std::cos(theta);
  y0[U] = u0;
  y0[V] = v0;
  y0[LAM] = y0[DY] = y0[DV] = 0;
  return build({"DummyPendulum", 7, names, y0, diff, res, jac, 1, pnames,
                params},
               set, tables);
}

// ---- R-L1-L2-C loop ----------------------------------------------------
// Unknowns i1, i2, vL1, vL2, vC, der(i2); p = {L1, L2, C, R}.
namespace cutset_detail {
enum { I1, I2, VL1, VL2, VC, DI2 };
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  r[0] = p[0] * yp[I1] - y[VL1];
  r[1] = p[1] * y[DI2] - y[VL2];
  r[2] = y[I1] - y[I2]; // the cutset: one current through both inductors
  r[3] = p[2] * yp[VC] - y[I1];
  r[4] = y[VL1] + y[VL2] + y[VC] + p[3] * y[I1];
  r[5] = yp[I1] - y[DI2]; // der(i1 = i2): made by index reduction
  return 0;
}
inline int jac(double, const double *, const double *, const double *p,
               double cj, double *J) {
  auto at = [J](int r, int c) -> double & { return J[r + 6 * c]; };
  for (int k = 0; k < 36; ++k)
    J[k] = 0;
  at(0, I1) = p[0] * cj;
  at(0, VL1) = -1;
  at(1, DI2) = p[1];
  at(1, VL2) = -1;
  at(2, I1) = 1;
  at(2, I2) = -1;
  at(3, VC) = p[2] * cj;
  at(3, I1) = -1;
  at(4, VL1) = 1;
  at(4, VL2) = 1;
  at(4, VC) = 1;
  at(4, I1) = p[3];
  at(5, I1) = cj;
  at(5, DI2) = -1;
  return 0;
}
} // namespace cutset_detail

inline ldae_model inductorCutset(const double (&LLCR)[4], double i1,
                                 double i2, double vc) {
  using namespace cutset_detail;
  static const char *names[] = {"i1", "i2", "vL1", "vL2", "vC", "der(i2)"};
  static double y0[6], params[4];
  static const int diff[] = {1, 0, 0, 0, 1, 0};
  static const int dummy[] = {-1, -1, -1, -1, -1, I2};
  static const int original[] = {1, 1, 1, 1, 1, 0};
  static const char *pnames[] = {"L1", "L2", "C", "R"};
  static ldae_state_set set{};
  static Tables tables{{dummy}, {original}};
  for (int k = 0; k < 4; ++k)
    params[k] = LLCR[k];
  y0[I1] = i1;
  y0[I2] = i2;
  y0[VC] = vc;
  y0[VL1] = y0[VL2] = y0[DI2] = 0;
  return build({"InductorCutset", 6, names, y0, diff, res, jac, 4, pnames,
                params},
               set, tables);
}

} // namespace jumpmodels
