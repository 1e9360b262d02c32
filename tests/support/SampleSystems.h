// Hand-built DaeSystems exercising code generation: used by the codegen unit
// tests and bench/codegen_bench.cpp (independent of the frontend and the
// structural passes). Test support (library ldae_test_samples), never
// linked into the compiler.
#pragma once

#include "ir/DaeSystem.h"

#include <memory>

namespace ldae::codegen::samples {

/// A DaeSystem with the Model it points to.
struct SampleSystem {
  std::unique_ptr<ir::Model> model;
  ir::DaeSystem sys;
};

/// Robertson's index-1 kinetics: y1, y2 differential, y3 algebraic;
/// one initial residual, one root, one drift constraint, four outputs.
SampleSystem robertson();

/// The pendulum reduced by hand to index 1 with dummy derivatives, two
/// state sets: {x, vx} (dummies der(y), der(vy)) and {y, vy} (dummies
/// der(x), der(vx)); 1x1 pivots y and x.
SampleSystem pendulum();

/// The Cartesian pendulum (x, y, u, v, lambda; g = 9.81, L = 1, released
/// from rest at the angle theta0 from the vertical, lambda consistent) in
/// the linearly implicit form `--method sga|ode` hands over: rows
/// x' - u, y' - v, u' + lambda x, v' + lambda y + g and the time derivative
/// of the third constraint (which holds lambda'), every unknown
/// differential; constraints x^2 + y^2 - L^2, x u + y v,
/// u^2 + v^2 - lambda (x^2 + y^2) - g y (also the drift). `project`: sga.
SampleSystem cartesianPendulumSga(double theta0, bool project);

/// Robertson's kinetics in the same form: y1, y2, y3 all differential,
/// the third row the derivative of y1 + y2 + y3 = 1 (the constraint).
SampleSystem robertsonSga(bool project);

/// n coupled nonlinear oscillators:
/// der(x[i]) = k*(x[i-1] - 2*x[i] + x[i+1]) - a*x[i]^3 (+ sin(t) at i = 0).
SampleSystem chain(unsigned n);

/// chain(n) with its unknowns laid out in a shuffled order, so that loops
/// over its equations read their slots from index tables, not strides.
SampleSystem shuffledChain(unsigned n);

/// chain(n) with the initial equations der(x[i]) x[i-1] = 0.1 x[i]^2 for
/// every second i: initial-equation Jacobians in y and y'.
SampleSystem initChain(unsigned n);

/// n algebraic unknowns with residuals log(x[i]) - 1: one loop whose
/// iterations hit a domain error where x[i] <= 0.
SampleSystem logChain(unsigned n);

/// n algebraic unknowns x[i] with x[i]^2 = 2 and s = sum of log(x[i]): a
/// long sum compiled as a reduction loop, with a domain check per term.
SampleSystem logSum(unsigned n);

/// Every built-in of the language applied to unknowns u, v (differential)
/// in residuals z[i] - f_i(u, v) and in outputs.
SampleSystem builtins();

/// Residuals with domain errors at chosen points (see the test).
SampleSystem domainErrors();

/// pendulum() with the jump rule's pencil: in set A der(y), der(vy) are
/// the dummies of y, vy, in set B der(x), der(vx) those of x, vx; rows 5
/// and 6 (the differentiated constraints) are not equations as written.
SampleSystem pendulumPencil();

/// Every part of the events block over a falling ball (h, v; g = 9.81,
/// e = 0.8, t0 = 0.5, ts = 0.1, ti = 0.2, hmax = 10). Discrete values:
///   0 `h <= 0` (relation, root h), 1 its when-condition,
///   2 `time >= t0` (time relation, threshold t0), 3 `on = time >= t0`
///   (a mode value: the residual reads `if on then g else g/2`),
///   4 `sample(ts, ti)`, 5 `count` (+1 on each sample tick), 6 initial().
/// `when h <= 0 then reinit(v, -e*pre(v))`, `when h > hmax then
/// terminate("too high")`, assert(h >= -0.001, "below ground") (error),
/// assert(abs(v) < 100, "too fast") (warning), outputs count, on, energy.
SampleSystem bouncingEvents();

/// The current value (Parameter(nParams + k)) and the pre() value
/// (Parameter(nParams + nDiscrete + k)) of discrete value k of `sys`.
ir::ExprRef discreteValue(const ir::DaeSystem &sys, unsigned k);
ir::ExprRef discretePre(const ir::DaeSystem &sys, unsigned k);

} // namespace ldae::codegen::samples
