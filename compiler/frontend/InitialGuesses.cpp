// Start values from initial equations. An initial equation that gives one
// unknown its value (`x = 1`, `n = {1.0, 2.0}`) says where the system
// starts better than the default start 0 does, and that default can lie
// outside an equation's domain or on a degenerate branch: OpenModelica's
// Issue13292 (`x*sum(n) = n` at n = 0 holds for every x, and x = n/sum(n)
// divides by zero), Decay3 (`der(x) = -sqrt(x)` at x = 0, an infinite
// derivative), ModelTestSolve. So such an unknown without a start value
// starts at that value (its binding re-evaluated when a parameter it reads
// changes); the initial equation stays a condition of the initialization.
// A start that reads such unknowns (`Real w(start = a)` with `parameter
// Real a(fixed = false)`) is evaluated from their starts after that.
#include "frontend/Frontend.h"

#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "ir/Substitute.h"

#include <cmath>

namespace ldae::frontend {

void startFromInitialEquations(ir::Model &model) {
  ir::EvalEnv env;
  env.variable = [](ir::VarKey) { return 0.0; };
  std::vector<double> params = model.parameterValues();
  env.parameter = [&params](ir::ParamId p) {
    return p < params.size() ? params[p] : 0.0;
  };
  env.time = model.experiment.startTime.value_or(0.0);
  for (const ir::Equation &eq : model.initialEquations) {
    std::vector<ir::VarKey> vars = ir::freeVariables(eq.residual);
    if (vars.size() != 1 || vars[0].order != 0 || ir::dependsOnTime(eq.residual))
      continue;
    ir::Variable &v = model.variables[vars[0].var];
    if (v.hasStart || v.fixed || v.isDiscrete)
      continue;
    ir::ExprRef value = ir::solveLinear(model.ctx(), eq.residual, vars[0].var);
    if (!value)
      continue;
    Expected<double> x = ir::evaluate(value, env, &model);
    if (!x || !std::isfinite(*x))
      continue;
    v.start = *x;
    v.hasStart = true;
    if (!ir::freeParameters(value).empty())
      v.startBinding = value;
  }
  // Start values that read other unknowns' (a parameter with fixed =
  // false), from those just given.
  env.variable = [&model](ir::VarKey k) {
    return k.order == 0 ? model.variables[k.var].start : 0.0;
  };
  for (ir::Variable &v : model.variables) {
    if (!v.startGuess)
      continue;
    Expected<double> x = ir::evaluate(v.startGuess, env, &model);
    if (x && std::isfinite(*x)) {
      v.start = *x;
      v.hasStart = true;
    }
  }
}

} // namespace ldae::frontend
