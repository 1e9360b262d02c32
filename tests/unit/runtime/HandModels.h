// Hand-written ldae_model structs for testing and benchmarking the runtime
// before (and independently of) the code generator: plain C++ functions
// with the ABI's signatures. Each maker returns a model whose arrays live in
// static storage.
//  - robertson(): the Robertson kinetics DAE as in SUNDIALS'
//    idaRoberts_dns.c (two root functions, nominal values that turn one
//    atol into that example's per-component atol).
//  - pendulum(eps): the Cartesian pendulum of length L(t) = L0 (1 + eps
//    sin(w t)) reduced by dummy derivatives by hand, with its two state
//    sets {x, u} and {y, v}; eps = 0 is the fixed-length pendulum.
//  - rcCircuit(): a capacitor charged through a resistor.
//  - logDomain(): a model whose residual leaves its domain at t = 1.
//  - index1Init(), index2Linear(): consistent-initialization examples.
//  - decayChain(k): 2k unknowns, CSC Jacobian (exercises KLU when > 32).
//  - coupledChain(k): 2k unknowns, nonlinear index 1 with the algebraic
//    unknowns coupled along the chain, CSC Jacobian only (the sparse
//    initialization).
#pragma once

#include "ldae/model.h"

#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

namespace handmodels {

inline ldae_model blankModel(const char *name, int n) {
  ldae_model m{};
  m.abi_version = LDAE_ABI_VERSION;
  m.name = name;
  m.n = n;
  m.n_state_sets = 1;
  m.start_time = m.stop_time = m.tolerance = m.interval = NAN;
  return m;
}

/// A model with the common fields set; one state set.
inline ldae_model makeModel(const char *name, int n, const char *const *names,
                            const double *y0, const double *yp0,
                            const double *nominal, const int *fixed,
                            const ldae_state_set *set) {
  ldae_model m = blankModel(name, n);
  m.var_names = names;
  m.start_y = y0;
  m.start_yp = yp0;
  m.nominal = nominal;
  m.fixed = fixed;
  m.state_sets = set;
  return m;
}

// ---- Robertson --------------------------------------------------------
namespace robertson_detail {
inline int res(double, const double *y, const double *yp, const double *,
               double *r) {
  double rate = -0.04 * y[0] + 1.0e4 * y[1] * y[2];
  r[0] = rate - yp[0];
  r[1] = -rate - 3.0e7 * y[1] * y[1] - yp[1];
  r[2] = y[0] + y[1] + y[2] - 1.0;
  return 0;
}
inline int jac(double, const double *y, const double *, const double *,
               double cj, double *J) {
  auto at = [J](int r, int c) -> double & { return J[r + 3 * c]; };
  at(0, 0) = -0.04 - cj;
  at(0, 1) = 1.0e4 * y[2];
  at(0, 2) = 1.0e4 * y[1];
  at(1, 0) = 0.04;
  at(1, 1) = -1.0e4 * y[2] - 6.0e7 * y[1] - cj;
  at(1, 2) = -1.0e4 * y[1];
  at(2, 0) = 1.0;
  at(2, 1) = 1.0;
  at(2, 2) = 1.0;
  return 0;
}
inline int roots(double, const double *y, const double *, const double *,
                 double *g) {
  g[0] = y[0] - 0.0001;
  g[1] = y[2] - 0.01;
  return 0;
}
} // namespace robertson_detail

inline ldae_model robertson() {
  using namespace robertson_detail;
  static const char *names[] = {"y1", "y2", "y3"};
  static const double y0[] = {1, 0, 0}, yp0[] = {-0.04, 0.04, 0};
  static const double nominal[] = {1, 100, 100};
  static const int fixed[] = {1, 1, 0};
  static const int diff[] = {1, 1, 0};
  static const char *origin[] = {"robertson.lsd:3", "robertson.lsd:4",
                                 "robertson.lsd:5"};
  static ldae_state_set set{};
  set.is_differential = diff;
  set.residual = res;
  set.jacobian_dense = jac;
  set.description = "states: y1, y2";
  ldae_model m =
      makeModel("Robertson", 3, names, y0, yp0, nominal, fixed, &set);
  m.n_roots = 2;
  m.roots = roots;
  m.residual_origin = origin;
  return m;
}

// ---- Pendulum (fixed or variable length), two state sets --------------
// Unknowns x, y, u, v, lam; p = {L0, g, eps, w}.
namespace pendulum_detail {
enum { X, Y, U, V, LAM };
struct Len {
  double L, dL, ddL;
};
inline Len length(double t, const double *p) {
  double L0 = p[0], e = p[2], w = p[3];
  return {L0 * (1 + e * std::sin(w * t)), L0 * e * w * std::cos(w * t),
          -L0 * e * w * w * std::sin(w * t)};
}
// Rows 2..4: the constraint, its derivative, and its second derivative
// with the dummy derivatives eliminated through the equations of motion.
inline void constraints(double t, const double *y, const double *p, double *r) {
  Len l = length(t, p);
  double g = p[1];
  r[2] = y[X] * y[X] + y[Y] * y[Y] - l.L * l.L;
  r[3] = y[X] * y[U] + y[Y] * y[V] - l.L * l.dL;
  r[4] = y[U] * y[U] + y[V] * y[V] - y[LAM] * (y[X] * y[X] + y[Y] * y[Y]) -
         g * y[Y] - l.dL * l.dL - l.L * l.ddL;
}
inline void constraintJac(const double *y, const double *p, double *J) {
  auto at = [J](int r, int c) -> double & { return J[r + 5 * c]; };
  double g = p[1];
  at(2, X) = 2 * y[X];
  at(2, Y) = 2 * y[Y];
  at(3, X) = y[U];
  at(3, Y) = y[V];
  at(3, U) = y[X];
  at(3, V) = y[Y];
  at(4, X) = -2 * y[LAM] * y[X];
  at(4, Y) = -2 * y[LAM] * y[Y] - g;
  at(4, U) = 2 * y[U];
  at(4, V) = 2 * y[V];
  at(4, LAM) = -(y[X] * y[X] + y[Y] * y[Y]);
}
// The state set with position Pos and velocity Vel as states (x, u or
// y, v); the other position and velocity are determined by the constraints
// (their derivatives are the dummies). Gravity acts on y.
template <int Pos, int Vel>
int res(double t, const double *y, const double *yp, const double *p,
        double *r) {
  r[0] = yp[Pos] - y[Vel];
  r[1] = yp[Vel] + y[LAM] * y[Pos] + (Pos == Y ? p[1] : 0.0);
  constraints(t, y, p, r);
  return 0;
}
template <int Pos, int Vel>
int jac(double, const double *y, const double *, const double *p, double cj,
        double *J) {
  for (int i = 0; i < 25; ++i)
    J[i] = 0;
  J[0 + 5 * Pos] = cj;
  J[0 + 5 * Vel] = -1;
  J[1 + 5 * Vel] = cj;
  J[1 + 5 * Pos] = y[LAM];
  J[1 + 5 * LAM] = y[Pos];
  constraintJac(y, p, J);
  return 0;
}
// Pivot: d(constraint)/d(the position the constraint determines).
template <int Other>
int pivot(double, const double *y, const double *, const double *, double *M) {
  M[0] = 2 * y[Other];
  return 0;
}
inline int drift(double t, const double *y, const double *, const double *p,
                 double *d) {
  double r[5];
  constraints(t, y, p, r);
  d[0] = r[2];
  d[1] = r[3];
  return 0;
}
} // namespace pendulum_detail

/// The pendulum released at angle theta0 (from the downward vertical) with
/// angular velocity omega0; lam starts at 0 (to be initialized).
inline ldae_model pendulum(double eps, double theta0, double omega0) {
  using namespace pendulum_detail;
  static const char *names[] = {"x", "y", "u", "v", "lam"};
  static double y0[5], yp0[5], params[4];
  static const double nominal[] = {1, 1, 1, 1, 1};
  static const int fixed[] = {0, 0, 0, 0, 0};
  static const int diffA[] = {1, 0, 1, 0, 0}, diffB[] = {0, 1, 0, 1, 0};
  static const char *pnames[] = {"L0", "g", "eps", "w"};
  static const char *origin[] = {"pendulum.lsd:8", "pendulum.lsd:9",
                                 "pendulum.lsd:10", "pendulum.lsd:10",
                                 "pendulum.lsd:10"};
  static ldae_state_set sets[2];
  params[0] = 1.0;
  params[1] = 9.81;
  params[2] = eps;
  params[3] = 1.3;
  Len l = length(0, params);
  y0[X] = l.L * std::sin(theta0);
  y0[Y] = -l.L * std::cos(theta0);
  y0[U] = l.dL * std::sin(theta0) + l.L * std::cos(theta0) * omega0;
  y0[V] = -l.dL * std::cos(theta0) + l.L * std::sin(theta0) * omega0;
  y0[LAM] = 0;
  for (double &v : yp0)
    v = 0;
  sets[0] = ldae_state_set{};
  sets[0].is_differential = diffA;
  sets[0].residual = res<X, U>;
  sets[0].jacobian_dense = jac<X, U>;
  sets[0].pivot_size = 1;
  sets[0].pivot = pivot<Y>;
  sets[0].description = "states: x, der(x)";
  sets[1] = sets[0];
  sets[1].is_differential = diffB;
  sets[1].residual = res<Y, V>;
  sets[1].jacobian_dense = jac<Y, V>;
  sets[1].pivot = pivot<X>;
  sets[1].description = "states: y, der(y)";
  ldae_model m = makeModel("Pendulum", 5, names, y0, yp0, nominal, fixed, sets);
  m.n_params = 4;
  m.param_names = pnames;
  m.param_values = params;
  m.n_state_sets = 2;
  m.n_drift = 2;
  m.drift = drift;
  m.residual_origin = origin;
  return m;
}

// ---- RC circuit -------------------------------------------------------
// Unknowns v (capacitor voltage), i; p = {R, C, V0}:
//   C v' = i,  R i = V0 - v;  v(0) = 0 fixed.
namespace rc_detail {
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  r[0] = p[1] * yp[0] - y[1];
  r[1] = p[0] * y[1] - (p[2] - y[0]);
  return 0;
}
inline int jac(double, const double *, const double *, const double *p,
               double cj, double *J) {
  J[0] = p[1] * cj; // (0,0)
  J[1] = 1;         // (1,0)
  J[2] = -1;        // (0,1)
  J[3] = p[0];      // (1,1)
  return 0;
}
} // namespace rc_detail

inline ldae_model rcCircuit() {
  static const char *names[] = {"C.v", "R.i"};
  static const double y0[] = {0, 0}, yp0[] = {0, 0}, nominal[] = {1, 1e-3};
  static const int fixed[] = {1, 0}, diff[] = {1, 0};
  static const char *pnames[] = {"R", "C", "V0"};
  static const double params[] = {1000, 1e-3, 1};
  static ldae_state_set set{};
  set.is_differential = diff;
  set.residual = rc_detail::res;
  set.jacobian_dense = rc_detail::jac;
  ldae_model m = makeModel("RC", 2, names, y0, yp0, nominal, fixed, &set);
  m.n_params = 3;
  m.param_names = pnames;
  m.param_values = params;
  m.stop_time = 5;
  return m;
}

// ---- A residual that leaves its domain --------------------------------
// y' = -1, z = log(y): at t = 1 the log's argument reaches 0.
namespace domain_detail {
inline int res(double, const double *y, const double *yp, const double *,
               double *r) {
  r[0] = yp[0] + 1;
  if (!(y[0] > 0))
    return 2; // row 1 (1-based 2): log of a non-positive number
  r[1] = y[1] - std::log(y[0]);
  return 0;
}
} // namespace domain_detail

inline ldae_model logDomain() {
  static const char *names[] = {"y", "z"};
  static const double y0[] = {1, 0}, yp0[] = {-1, 0}, nominal[] = {1, 1};
  static const int fixed[] = {1, 0}, diff[] = {1, 0};
  static const char *origin[] = {"domain.lsd:3", "domain.lsd:4"};
  static ldae_state_set set{};
  set.is_differential = diff;
  set.residual = domain_detail::res;
  ldae_model m =
      makeModel("LogDomain", 2, names, y0, yp0, nominal, fixed, &set);
  m.residual_origin = origin;
  return m;
}

// ---- Initialization examples ------------------------------------------
// Index 1: x' = -x + z, 0 = z - 2 x. Start x = 1, z = 5 (inconsistent);
// `fixZ` makes z = 4 a fixed condition instead.
namespace init_detail {
inline int res1(double, const double *y, const double *yp, const double *,
                double *r) {
  r[0] = yp[0] + y[0] - y[1];
  r[1] = y[1] - 2 * y[0];
  return 0;
}
// Index 2, linear, constant coefficients (unknowns x1, x2, x3; p = {c}):
//   x1' = x2,  x3' = x2 - x3,  0 = x1 - c.
inline int res2(double, const double *y, const double *yp, const double *p,
                double *r) {
  r[0] = yp[0] - y[1];
  r[1] = yp[2] - y[1] + y[2];
  r[2] = y[0] - p[0];
  return 0;
}
inline int jac2(double, const double *, const double *, const double *,
                double cj, double *J) {
  for (int i = 0; i < 9; ++i)
    J[i] = 0;
  J[0 + 3 * 0] = cj;
  J[0 + 3 * 1] = -1;
  J[1 + 3 * 2] = cj + 1;
  J[1 + 3 * 1] = -1;
  J[2 + 3 * 0] = 1;
  return 0;
}
} // namespace init_detail

inline ldae_model index1Init(bool fixZ) {
  static const char *names[] = {"x", "z"};
  static double y0[2];
  static const double yp0[] = {0, 0}, nominal[] = {1, 1};
  static int fixed[2];
  static const int diff[] = {1, 0};
  static ldae_state_set set{};
  y0[0] = 1;
  y0[1] = fixZ ? 4 : 5;
  fixed[0] = 0;
  fixed[1] = fixZ;
  set.is_differential = diff;
  set.residual = init_detail::res1; // Jacobian by difference quotients
  ldae_model m =
      makeModel("Index1Init", 2, names, y0, yp0, nominal, fixed, &set);
  return m;
}

inline ldae_model index2Linear(double x1, double x2, double x3, double c) {
  static const char *names[] = {"x1", "x2", "x3"};
  static double y0[3], params[1];
  static const double yp0[] = {0, 0, 0}, nominal[] = {1, 1, 1};
  static const int fixed[] = {0, 0, 0}, diff[] = {1, 0, 1};
  static const char *pnames[] = {"c"};
  static ldae_state_set set{};
  y0[0] = x1;
  y0[1] = x2;
  y0[2] = x3;
  params[0] = c;
  set.is_differential = diff;
  set.residual = init_detail::res2;
  set.jacobian_dense = init_detail::jac2;
  ldae_model m =
      makeModel("Index2Linear", 3, names, y0, yp0, nominal, fixed, &set);
  m.n_params = 1;
  m.param_names = pnames;
  m.param_values = params;
  return m;
}

// ---- The unreduced index-3 pendulum (the `raw` method's system) ---------
// x' = vx, y' = vy, vx' = -lam x, vy' = -lam y - g, 0 = x^2 + y^2 - 1;
// at rest at angle theta0, x and vx fixed, lam to be initialized.
namespace raw_detail {
inline int res(double, const double *y, const double *yp, const double *,
               double *r) {
  r[0] = yp[0] - y[2];
  r[1] = yp[1] - y[3];
  r[2] = yp[2] + y[4] * y[0];
  r[3] = yp[3] + y[4] * y[1] + 9.81;
  r[4] = y[0] * y[0] + y[1] * y[1] - 1;
  return 0;
}
} // namespace raw_detail

inline ldae_model rawPendulum(double theta0) {
  static const char *names[] = {"x", "y", "vx", "vy", "lambda"};
  static double y0[5];
  static const double yp0[5] = {0, 0, 0, 0, 0}, nominal[] = {1, 1, 1, 1, 1};
  static const int fixed[] = {1, 0, 1, 0, 0}, diff[] = {1, 1, 1, 1, 0};
  static ldae_state_set set{};
  y0[0] = std::sin(theta0);
  y0[1] = -std::cos(theta0);
  y0[2] = y0[3] = y0[4] = 0;
  set.is_differential = diff;
  set.residual = raw_detail::res; // Jacobian by difference quotients
  ldae_model m =
      makeModel("RawPendulum", 5, names, y0, yp0, nominal, fixed, &set);
  return m;
}

// ---- A chain with a sparse Jacobian -----------------------------------
// Unknowns (y_i, z_i), i < k: y_i' = -a_i z_i, 0 = z_i - y_i, a_i = 0.1 (i+1).
namespace chain_detail {
inline int k(const double *p) { return int(p[0]); }
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  for (int i = 0; i < k(p); ++i) {
    r[2 * i] = yp[2 * i] + 0.1 * (i + 1) * y[2 * i + 1];
    r[2 * i + 1] = y[2 * i + 1] - y[2 * i];
  }
  return 0;
}
// CSC: column 2i (y_i) has rows 2i (cj) and 2i+1 (-1); column 2i+1 (z_i)
// has rows 2i (a_i) and 2i+1 (1).
inline int jacCsc(double, const double *, const double *, const double *p,
                  double cj, double *v) {
  for (int i = 0; i < k(p); ++i) {
    v[4 * i + 0] = cj;
    v[4 * i + 1] = -1;
    v[4 * i + 2] = 0.1 * (i + 1);
    v[4 * i + 3] = 1;
  }
  return 0;
}
} // namespace chain_detail

/// Storage of a chain model with a CSC Jacobian (2k unknowns, parameter
/// k): each maker keeps one in static storage, as the other models' arrays.
struct ChainStore {
  std::vector<double> y0, yp0, nominal, params;
  std::vector<int> fixed, diff, colptr, rowind;
  ldae_state_set set{};

  void reset(int k) {
    int n = 2 * k;
    y0.assign(n, 0.0);
    yp0.assign(n, 0.0);
    nominal.assign(n, 1.0);
    fixed.assign(n, 0);
    diff.assign(n, 0);
    colptr.assign(1, 0);
    rowind.clear();
    params.assign(1, k);
  }
  /// Appends the next column of the pattern.
  void column(std::initializer_list<int> rows) {
    rowind.insert(rowind.end(), rows);
    colptr.push_back(int(rowind.size()));
  }
  ldae_model model(const char *name, const char *const *names,
                   ldae_residual_fn res, ldae_jacobian_csc_fn jac) {
    set = ldae_state_set{};
    set.is_differential = diff.data();
    set.residual = res;
    set.jacobian_csc = jac;
    set.jac_nnz = int(rowind.size());
    set.jac_colptr = colptr.data();
    set.jac_rowind = rowind.data();
    ldae_model m = makeModel(name, int(y0.size()), names, y0.data(),
                             yp0.data(), nominal.data(), fixed.data(), &set);
    m.n_params = 1;
    m.param_values = params.data();
    return m;
  }
};

inline ldae_model decayChain(int k) {
  static ChainStore store;
  static std::vector<std::string> nameStore;
  static std::vector<const char *> names;
  store.reset(k);
  nameStore.clear();
  names.clear();
  for (int i = 0; i < k; ++i) {
    store.y0[2 * i] = store.y0[2 * i + 1] = 1.0;
    store.diff[2 * i] = 1;
    store.fixed[2 * i] = 1;
    nameStore.push_back("y" + std::to_string(i + 1));
    nameStore.push_back("z" + std::to_string(i + 1));
    store.column({2 * i, 2 * i + 1});
    store.column({2 * i, 2 * i + 1});
  }
  for (auto &s : nameStore)
    names.push_back(s.c_str());
  return store.model("DecayChain", names.data(), chain_detail::res,
                     chain_detail::jacCsc);
}

// ---- A nonlinear index-1 chain with coupled algebraic unknowns ---------
// Unknowns (y_i, z_i), i < k, a_i = 0.1 (i + 1):
//   y_i' = -a_i z_i,
//   0 = z_i + 0.5 tanh(z_i) - y_i^2 - 0.1 z_{i+1}   (no z_{i+1} for the last),
// so the algebraic values form one bidiagonal nonlinear system along the
// chain. Start y_i = 1 + 0.001 i, z = 0, y' = 0.
namespace coupled_detail {
inline int k(const double *p) { return int(p[0]); }
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  int n = k(p);
  for (int i = 0; i < n; ++i) {
    double z = y[2 * i + 1], next = i + 1 < n ? y[2 * i + 3] : 0.0;
    r[2 * i] = yp[2 * i] + 0.1 * (i + 1) * z;
    r[2 * i + 1] =
        z + 0.5 * std::tanh(z) - y[2 * i] * y[2 * i] - 0.1 * next;
  }
  return 0;
}
// CSC, rows sorted: column y_i has rows 2i (cj), 2i+1 (-2 y_i); column z_i
// has row 2i-1 (-0.1, for i > 0), 2i (a_i), 2i+1 (1 + 0.5 sech^2 z_i).
inline int jacCsc(double, const double *y, const double *, const double *p,
                  double cj, double *v) {
  int q = 0;
  for (int i = 0; i < k(p); ++i) {
    double th = std::tanh(y[2 * i + 1]);
    v[q++] = cj;
    v[q++] = -2 * y[2 * i];
    if (i > 0)
      v[q++] = -0.1;
    v[q++] = 0.1 * (i + 1);
    v[q++] = 1 + 0.5 * (1 - th * th);
  }
  return 0;
}
} // namespace coupled_detail

inline ldae_model coupledChain(int k) {
  static ChainStore store;
  store.reset(k);
  for (int i = 0; i < k; ++i) {
    store.y0[2 * i] = 1 + 0.001 * i;
    store.diff[2 * i] = 1;
    store.column({2 * i, 2 * i + 1});
    if (i > 0)
      store.column({2 * i - 1, 2 * i, 2 * i + 1});
    else
      store.column({2 * i, 2 * i + 1});
  }
  return store.model("CoupledChain", nullptr, coupled_detail::res,
                     coupled_detail::jacCsc);
}

} // namespace handmodels
