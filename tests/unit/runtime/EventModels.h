// Hand-written ldae_model structs with events (ABI 6), as the compiler
// would fill them (docs/events.md): discrete values after the parameters
// in p, relation slots with their roots, when conditions, event_update,
// time events. Each maker returns a model whose arrays live in static
// storage.
//  - bouncingBall(e): h'' = -g, `when h <= 0 then reinit(v, -e*pre(v))`.
//  - sampledCounter(): `when sample(0.1, 0.1) then count = pre(count) + 1`,
//    der(x) = count.
//  - timeThreshold(t0): der(x) = if time >= t0 then 1 else 0.
//  - hysteresis(): der(T) = if heat then 1 else -1; `when T < 0.2 then
//    heat = true; elsewhen T > 0.8 then heat = false`.
//  - togglingWhen(): der(x) = s; `when x <= 0 then s = 1; elsewhen x > 0
//    then s = -1`: chatters at x = 0 from t = 1 on.
//  - resetNear(c): der(x) = 1; `when x >= c then reinit(x, 0)`.
//  - switchedMode(mode): the model of one mode of `if time >= 1 then
//    der(x) = -x else der(x) = 1` compiled as a variable structure.
//  - stopper(): der(x) = 1; `when x >= 0.5 then terminate("x reached
//    0.5")`; assert(x < limit, "x stays below the limit"), limit = 0.65.
#pragma once

#include "HandModels.h"

namespace handmodels {

namespace event_detail {
/// The discrete value k of p (the model's n_params parameters first).
inline double disc(const double *p, int np, int k) { return p[np + k]; }
inline double pre(const double *p, int np, int nd, int k) {
  return p[np + nd + k];
}
/// der(y[i]) = f: the explicit ODE row.
inline ldae_model odeModel(const char *name, int n, const char *const *names,
                           const double *y0, const double *yp0,
                           const ldae_state_set *set) {
  static const double nominal[] = {1, 1, 1, 1};
  static const int fixed[] = {1, 1, 1, 1};
  ldae_model m = makeModel(name, n, names, y0, yp0, nominal, fixed, set);
  m.explicit_ode = 1;
  m.algebraic_error_test = 1;
  return m;
}
/// out = {y[0], discrete value K}: a state and a discrete variable.
template <int NP, int K>
int stateAndDiscrete(double, const double *y, const double *, const double *p,
                     double *out) {
  out[0] = y[0];
  out[1] = disc(p, NP, K);
  return 0;
}
/// Slots {relation a, relation b, when a, when b, v} of `when a then v =
/// onA; elsewhen b then v = onB` (out[0], out[1] the relations' values).
template <int NP, int ND>
void elsewhenPair(const double *p, double *out, double onA, double onB) {
  out[2] = out[0];
  out[3] = out[1];
  bool a = out[2] != 0 && pre(p, NP, ND, 2) == 0;
  bool b = out[3] != 0 && pre(p, NP, ND, 3) == 0;
  out[4] = a ? onA : b ? onB : pre(p, NP, ND, 4);
}
/// The discrete state and the event update of `m`.
template <size_t ND>
void setDiscrete(ldae_model &m, const char *const (&names)[ND],
                 const double (&start)[ND], const int (&kinds)[ND],
                 ldae_outputs_fn update) {
  m.n_discrete = int(ND);
  m.discrete_names = names;
  m.discrete_start = start;
  m.discrete_kind = kinds;
  m.event_update = update;
}
/// Roots: one per relation, root j of relation rel[j].
template <size_t NR>
void setRoots(ldae_model &m, ldae_roots_fn roots, const int (&rel)[NR]) {
  m.n_roots = int(NR);
  m.roots = roots;
  m.root_relation = rel;
}
template <size_t NP>
void setParams(ldae_model &m, const char *const (&names)[NP],
               const double (&values)[NP]) {
  m.n_params = int(NP);
  m.param_names = names;
  m.param_values = values;
}
inline ldae_state_set stateSet(ldae_residual_fn res, const int *diff) {
  ldae_state_set s{};
  s.is_differential = diff;
  s.residual = res;
  return s;
}
} // namespace event_detail

// ---- Bouncing ball ----------------------------------------------------
// y = {h, v}; p = {g, e | h <= 0, when | pre}.
namespace ball_detail {
using namespace event_detail;
enum { NP = 2, ND = 2 };
inline int res(double, const double *y, const double *yp, const double *p,
               double *r) {
  r[0] = yp[0] - y[1];
  r[1] = yp[1] + p[0];
  return 0;
}
inline int roots(double, const double *y, const double *, const double *,
                 double *g) {
  g[0] = y[0];
  return 0;
}
inline int update(double, const double *y, const double *, const double *p,
                  double *out) {
  out[0] = y[0] <= 0;
  out[1] = out[0];
  out[2] = -p[1] * y[1];                          // reinit value
  out[3] = out[1] != 0 && pre(p, NP, ND, 1) == 0; // fired
  return 0;
}
} // namespace ball_detail

inline ldae_model bouncingBall(double e) {
  using namespace ball_detail;
  static const char *names[] = {"h", "v"};
  static const double y0[] = {1, 0}, yp0[] = {0, -9.81};
  static const int diff[] = {1, 1};
  static double params[NP] = {};
  static const char *pnames[] = {"g", "e"};
  static const char *dnames[] = {"h <= 0", "when h <= 0"};
  static const double dstart[] = {0, 0};
  static const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_WHEN};
  static const int rootRel[] = {0}, target[] = {1};
  static ldae_state_set set = stateSet(res, diff);
  params[0] = 9.81;
  params[1] = e;
  ldae_model m = odeModel("BouncingBall", 2, names, y0, yp0, &set);
  setParams(m, pnames, params);
  setRoots(m, roots, rootRel);
  setDiscrete(m, dnames, dstart, kinds, update);
  m.n_reinit = 1;
  m.reinit_target = target;
  return m;
}

// ---- Sampled counter --------------------------------------------------
// y = {x}; p = {sample, when, count | pre}.
namespace counter_detail {
using namespace event_detail;
enum { NP = 0, ND = 3 };
inline int res(double, const double *, const double *yp, const double *p,
               double *r) {
  r[0] = yp[0] - disc(p, NP, 2);
  return 0;
}
inline int update(double, const double *, const double *, const double *p,
                  double *out) {
  out[0] = disc(p, NP, 0);
  out[1] = out[0];
  bool fire = out[1] != 0 && pre(p, NP, ND, 1) == 0;
  out[2] = fire ? pre(p, NP, ND, 2) + 1 : pre(p, NP, ND, 2);
  return 0;
}
inline int timeEvents(double, const double *, const double *, const double *,
                      double *out) {
  out[0] = 0.1;
  out[1] = 0.1;
  return 0;
}
constexpr ldae_outputs_fn outputs = stateAndDiscrete<NP, 2>;
} // namespace counter_detail

inline ldae_model sampledCounter() {
  using namespace counter_detail;
  static const char *names[] = {"x"};
  static const char *outNames[] = {"x", "count"};
  static const double y0[] = {0}, yp0[] = {0};
  static const int diff[] = {1};
  static const char *dnames[] = {"sample(0.1, 0.1)", "when sample(0.1, 0.1)",
                                 "count"};
  static const double dstart[] = {0, 0, 0};
  static const int kinds[] = {LDAE_DISCRETE_SAMPLE, LDAE_DISCRETE_WHEN,
                              LDAE_DISCRETE_VARIABLE};
  static const int sampleDisc[] = {0};
  static ldae_state_set set = stateSet(res, diff);
  ldae_model m = odeModel("SampledCounter", 1, names, y0, yp0, &set);
  m.n_outputs = 2;
  m.output_names = outNames;
  m.outputs = outputs;
  setDiscrete(m, dnames, dstart, kinds, update);
  m.n_samples = 1;
  m.sample_discrete = sampleDisc;
  m.time_events = timeEvents;
  return m;
}

// ---- A time relation --------------------------------------------------
// y = {x}; p = {t0 | time >= t0 | pre}.
namespace threshold_detail {
using namespace event_detail;
enum { NP = 1, ND = 1 };
inline int res(double, const double *, const double *yp, const double *p,
               double *r) {
  r[0] = yp[0] - disc(p, NP, 0);
  return 0;
}
inline int update(double t, const double *, const double *, const double *p,
                  double *out) {
  out[0] = t >= p[0];
  return 0;
}
inline int timeEvents(double, const double *, const double *, const double *p,
                      double *out) {
  out[0] = p[0];
  return 0;
}
} // namespace threshold_detail

inline ldae_model timeThreshold(double t0) {
  using namespace threshold_detail;
  static const char *names[] = {"x"};
  static const double y0[] = {0}, yp0[] = {0};
  static const int diff[] = {1};
  static double params[NP] = {};
  static const char *pnames[] = {"t0"};
  static const char *dnames[] = {"time >= t0"};
  static const double dstart[] = {0};
  static const int kinds[] = {LDAE_DISCRETE_RELATION};
  static const int thresholdRel[] = {0};
  static ldae_state_set set = stateSet(res, diff);
  params[0] = t0;
  ldae_model m = odeModel("TimeThreshold", 1, names, y0, yp0, &set);
  setParams(m, pnames, params);
  setDiscrete(m, dnames, dstart, kinds, update);
  m.n_time_thresholds = 1;
  m.threshold_relation = thresholdRel;
  m.time_events = timeEvents;
  return m;
}

// ---- Hysteresis -------------------------------------------------------
// y = {T}; p = {T < 0.2, T > 0.8, when 1, when 2, heat | pre}.
namespace hysteresis_detail {
using namespace event_detail;
enum { NP = 0, ND = 5 };
inline int res(double, const double *, const double *yp, const double *p,
               double *r) {
  r[0] = yp[0] - (disc(p, NP, 4) != 0 ? 1.0 : -1.0);
  return 0;
}
inline int roots(double, const double *y, const double *, const double *,
                 double *g) {
  g[0] = y[0] - 0.2;
  g[1] = y[0] - 0.8;
  return 0;
}
inline int update(double, const double *y, const double *, const double *p,
                  double *out) {
  out[0] = y[0] < 0.2;
  out[1] = y[0] > 0.8;
  elsewhenPair<NP, ND>(p, out, 1.0, 0.0);
  return 0;
}
constexpr ldae_outputs_fn outputs = stateAndDiscrete<NP, 4>;
} // namespace hysteresis_detail

inline ldae_model hysteresis() {
  using namespace hysteresis_detail;
  static const char *names[] = {"T"};
  static const char *outNames[] = {"T", "heat"};
  static const double y0[] = {0.5}, yp0[] = {1};
  static const int diff[] = {1};
  static const char *dnames[] = {"T < 0.2", "T > 0.8", "when T < 0.2",
                                 "when T > 0.8", "heat"};
  static const double dstart[] = {0, 0, 0, 0, 1};
  static const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_RELATION,
                              LDAE_DISCRETE_WHEN, LDAE_DISCRETE_WHEN,
                              LDAE_DISCRETE_VARIABLE};
  static const int rootRel[] = {0, 1};
  static ldae_state_set set = stateSet(res, diff);
  ldae_model m = odeModel("Hysteresis", 1, names, y0, yp0, &set);
  m.n_outputs = 2;
  m.output_names = outNames;
  m.outputs = outputs;
  setRoots(m, roots, rootRel);
  setDiscrete(m, dnames, dstart, kinds, update);
  return m;
}

// ---- A when that toggles for ever -------------------------------------
// y = {x}; p = {x <= 0, x > 0, when 1, when 2, s | pre}.
namespace toggle_detail {
using namespace event_detail;
enum { NP = 0, ND = 5 };
inline int res(double, const double *, const double *yp, const double *p,
               double *r) {
  r[0] = yp[0] - disc(p, NP, 4);
  return 0;
}
inline int roots(double, const double *y, const double *, const double *,
                 double *g) {
  g[0] = y[0];
  g[1] = y[0];
  return 0;
}
inline int update(double, const double *y, const double *, const double *p,
                  double *out) {
  out[0] = y[0] <= 0;
  out[1] = y[0] > 0;
  elsewhenPair<NP, ND>(p, out, 1.0, -1.0);
  return 0;
}
} // namespace toggle_detail

inline ldae_model togglingWhen() {
  using namespace toggle_detail;
  static const char *names[] = {"x"};
  static const double y0[] = {1}, yp0[] = {-1};
  static const int diff[] = {1};
  static const char *dnames[] = {"x <= 0", "x > 0", "when x <= 0", "when x > 0",
                                 "s"};
  static const double dstart[] = {0, 1, 0, 1, -1};
  static const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_RELATION,
                              LDAE_DISCRETE_WHEN, LDAE_DISCRETE_WHEN,
                              LDAE_DISCRETE_VARIABLE};
  static const int rootRel[] = {0, 1};
  static ldae_state_set set = stateSet(res, diff);
  ldae_model m = odeModel("TogglingWhen", 1, names, y0, yp0, &set);
  setRoots(m, roots, rootRel);
  setDiscrete(m, dnames, dstart, kinds, update);
  return m;
}

// ---- A reset near the stop time ---------------------------------------
// y = {x}; p = {c | x >= c, when | pre}.
namespace reset_detail {
using namespace event_detail;
enum { NP = 1, ND = 2 };
inline int res(double, const double *, const double *yp, const double *,
               double *r) {
  r[0] = yp[0] - 1;
  return 0;
}
inline int roots(double, const double *y, const double *, const double *p,
                 double *g) {
  g[0] = y[0] - p[0];
  return 0;
}
inline int update(double, const double *y, const double *, const double *p,
                  double *out) {
  out[0] = y[0] >= p[0];
  out[1] = out[0];
  out[2] = 0;
  out[3] = out[1] != 0 && pre(p, NP, ND, 1) == 0;
  return 0;
}
} // namespace reset_detail

inline ldae_model resetNear(double c) {
  using namespace reset_detail;
  static const char *names[] = {"x"};
  static const double y0[] = {0}, yp0[] = {1};
  static const int diff[] = {1};
  static double params[NP] = {};
  static const char *pnames[] = {"c"};
  static const char *dnames[] = {"x >= c", "when x >= c"};
  static const double dstart[] = {0, 0};
  static const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_WHEN};
  static const int rootRel[] = {0}, target[] = {0};
  static ldae_state_set set = stateSet(res, diff);
  params[0] = c;
  ldae_model m = odeModel("ResetNear", 1, names, y0, yp0, &set);
  setParams(m, pnames, params);
  setRoots(m, roots, rootRel);
  setDiscrete(m, dnames, dstart, kinds, update);
  m.n_reinit = 1;
  m.reinit_target = target;
  return m;
}

// ---- A variable structure: one model per mode ---------------------------
// y = {x}; p = {time >= 1 | pre}.
namespace mode_detail {
using namespace event_detail;
enum { NP = 0, ND = 1 };
inline int resBefore(double, const double *, const double *yp, const double *,
                     double *r) {
  r[0] = yp[0] - 1;
  return 0;
}
inline int resAfter(double, const double *y, const double *yp, const double *,
                    double *r) {
  r[0] = yp[0] + y[0];
  return 0;
}
inline int update(double t, const double *, const double *, const double *,
                  double *out) {
  out[0] = t >= 1;
  return 0;
}
inline int timeEvents(double, const double *, const double *, const double *,
                      double *out) {
  out[0] = 1;
  return 0;
}
} // namespace mode_detail

/// mode 0: der(x) = 1 (time < 1); mode 1: der(x) = -x.
inline ldae_model switchedMode(int mode) {
  using namespace mode_detail;
  static const char *names[] = {"x"};
  static const double y0[] = {0}, yp0[] = {1};
  static const int diff[] = {1};
  static const char *dnames[] = {"time >= 1"};
  static const double dstart[] = {0};
  static const int kinds[] = {LDAE_DISCRETE_RELATION};
  static const int thresholdRel[] = {0}, modeDisc[] = {0};
  static const double modeValues[2][1] = {{0}, {1}};
  static ldae_state_set sets[2] = {stateSet(resBefore, diff),
                                   stateSet(resAfter, diff)};
  ldae_model m = odeModel("SwitchedMode", 1, names, y0, yp0, &sets[mode]);
  setDiscrete(m, dnames, dstart, kinds, update);
  m.n_time_thresholds = 1;
  m.threshold_relation = thresholdRel;
  m.time_events = timeEvents;
  m.n_mode = 1;
  m.mode_discrete = modeDisc;
  m.mode_values = modeValues[mode];
  return m;
}

// ---- terminate() and assert() -----------------------------------------
// y = {x}; p = {limit | x >= 0.5, when | pre}.
namespace stopper_detail {
using namespace event_detail;
enum { NP = 1, ND = 2 };
inline int res(double, const double *, const double *yp, const double *,
               double *r) {
  r[0] = yp[0] - 1;
  return 0;
}
inline int roots(double, const double *y, const double *, const double *,
                 double *g) {
  g[0] = y[0] - 0.5;
  return 0;
}
inline int update(double, const double *y, const double *, const double *p,
                  double *out) {
  out[0] = y[0] >= 0.5;
  out[1] = out[0];
  return 0;
}
inline int updateTerminating(double t, const double *y, const double *yp,
                             const double *p, double *out) {
  update(t, y, yp, p, out);
  out[2] = out[1] != 0 && pre(p, NP, ND, 1) == 0; // terminate fired
  return 0;
}
inline int asserts(double, const double *y, const double *, const double *p,
                   double *out) {
  out[0] = y[0] < p[0];
  out[1] = y[0] < 0.3;
  return 0;
}
} // namespace stopper_detail

/// `terminating`: whether the when-clause terminates the run (else it has
/// no terminate and the run meets the asserts).
inline ldae_model stopper(bool terminating) {
  using namespace stopper_detail;
  static const char *names[] = {"x"};
  static const double y0[] = {0}, yp0[] = {1};
  static const int diff[] = {1};
  static double params[NP] = {};
  static const char *pnames[] = {"limit"};
  static const char *dnames[] = {"x >= 0.5", "when x >= 0.5"};
  static const double dstart[] = {0, 0};
  static const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_WHEN};
  static const int rootRel[] = {0};
  static const char *termMsg[] = {"x reached 0.5"};
  static const char *assertMsg[] = {"x stays below the limit", "x is small"};
  static const int assertLevel[] = {0, 1};
  static const char *assertOrigin[] = {"stopper.lsd:7:3", "stopper.lsd:8:3"};
  static ldae_state_set set = stateSet(res, diff);
  params[0] = 0.65;
  ldae_model m = odeModel("Stopper", 1, names, y0, yp0, &set);
  setParams(m, pnames, params);
  setRoots(m, roots, rootRel);
  setDiscrete(m, dnames, dstart, kinds,
              terminating ? updateTerminating : update);
  m.n_terminate = terminating ? 1 : 0;
  m.terminate_message = termMsg;
  m.n_asserts = 2;
  m.assert_message = assertMsg;
  m.assert_level = assertLevel;
  m.assert_origin = assertOrigin;
  m.asserts = asserts;
  return m;
}

} // namespace handmodels
