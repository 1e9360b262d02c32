// Pass "sga-system" (`--method sga|ode`): the SGA's vector field on P_f as
// the DaeSystem the runtime integrates with CVODE. Its unknowns are the
// SGA's coordinates, all differential: each unknown and its derivatives
// below the top order (those get fresh variables named `der(x)`, as in
// build-system, so that no Variable node is read both as y and as y');
// its rows are the identities der(slot k) = slot k+1 and the rows whose
// A-parts are independent on P_f (the model's own equations first, the
// tangency rows where those do not suffice), linear in y'; its
// constraints are every constraint generation, onto which `sga` projects
// after each step.
#include "passes/Events.h"
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/Sga.h"

namespace ldae::passes {

namespace {

class SgaSystemPass
    : public TypedPass<SgaSystemPass,
                       Reads<SgaResult>,
                       Updates<>, Produces<ir::DaeSystem>> {
public:
  SgaSystemPass() : TypedPass(PassId::SgaSystem) {}
  bool runOn(PassContext &pc, const SgaResult &sga, ir::DaeSystem &out);
};

bool SgaSystemPass::runOn(PassContext &pc, const SgaResult &sga,
                          ir::DaeSystem &out) {
  return buildSgaSystem(pc, sga, pc.opts.method != Method::Ode, out);
}

} // namespace

bool buildSgaSystem(PassContext &pc, const SgaResult &sga, bool project,
                    ir::DaeSystem &out) {
  ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  if (!sga.ran) {
    pc.diags.report(DiagId::ErrIndexReductionFailed, m.loc,
                    {"the geometric algorithm could not run: " + sga.skipped});
    return false;
  }
  ir::DaeSystem sys;
  sys.ctx = m.sharedCtx();
  sys.model = &m;
  sys.index = 0;
  sys.form = ir::SystemForm::LinearlyImplicit;
  sys.projectOntoConstraints = project;

  VarSubstitution subst(ctx);
  ir::StateSet st;
  const SgaForm &f = sga.form;
  for (size_t j = 0; j < f.columns.size(); ++j) {
    const ir::VarId v = f.columns[j].var;
    const ir::Variable var = m.variables[v]; // copy: addVariable may realloc
    const unsigned top = f.top[j];
    std::vector<ir::VarKey> keys;
    for (unsigned k = 0; k < top; ++k) {
      ir::VarKey key{v, 0};
      if (k > 0) {
        ir::Variable fresh;
        fresh.name = m.variableName(ir::VarKey{v, k});
        fresh.component = var.component;
        fresh.loc = var.loc;
        fresh.nominal = var.nominal;
        key = {m.addVariable(fresh), 0};
        subst.set({v, k}, ctx.var(key));
      }
      keys.push_back(key);
      ir::SystemUnknown u;
      u.key = key;
      u.name = m.variableName(ir::VarKey{v, k});
      u.differential = true;
      u.start = k == 0 ? var.start : 0.0;
      // A guess only where the model gives no value: `x(fixed = true)`
      // without a start fixes x at the default start 0 (OpenModelica's
      // ASSC test started at the sampler's x = 10).
      if (k == 0 && !var.hasStart && !var.fixed &&
          sys.unknowns.size() < sga.startGuess.size())
        u.start = sga.startGuess[sys.unknowns.size()];
      u.startBinding = k == 0 ? var.startBinding : nullptr;
      u.nominal = var.nominal;
      u.fixed = k == 0 && var.fixed;
      u.loc = var.loc;
      sys.unknowns.push_back(u);
    }
    if (top >= 2)
      subst.set({v, top}, ctx.var(keys.back().var, 1));
    for (unsigned k = 0; k + 1 < top; ++k) {
      st.residuals.push_back(ctx.sub(ctx.var(keys[k].var, keys[k].order + 1),
                                     ctx.var(keys[k + 1])));
      sys.residualLocs.push_back(var.loc);
      sys.writtenResiduals.push_back(st.residuals.back());
    }
  }
  for (int r : sga.pivotRows) {
    const SgaRow &row = sga.rows[static_cast<size_t>(r)];
    st.residuals.push_back(subst.apply(row.residual));
    sys.residualLocs.push_back(m.equations[row.sources.front()].loc);
  }
  const size_t n = sys.unknowns.size();
  if (st.residuals.size() != n) {
    pc.diags.report(DiagId::ErrIndexReductionFailed, m.loc,
                    {"the vector field on P_f has " +
                     std::to_string(st.residuals.size()) + " rows for " +
                     std::to_string(n) + " coordinates"});
    return false;
  }
  st.differential.assign(n, true);
  for (const ir::SystemUnknown &u : sys.unknowns)
    st.states.push_back(u.name);
  sys.stateSets.push_back(std::move(st));
  for (const SgaConstraintExpr &c : sga.constraints)
    sys.constraints.push_back(subst.apply(c.expr));
  for (const ir::Equation &e : m.initialEquations)
    sys.initialResiduals.push_back(subst.apply(e.residual));
  // The SGA ran before alias elimination: every variable is its own.
  AliasResult noAliases;
  noAliases.eliminated.assign(sga.input.unknownIndex.size(), 0);
  if (!buildOutputs(pc, noAliases, sga.input, subst, sys.outputs))
    return false;
  if (pc.events &&
      !fillEvents(pc, *pc.events,
                  [&](ir::ExprRef e) { return subst.apply(e); }, sys))
    return false;
  // The model as written, for the jump rule (seed 002) at the start and
  // after events: its own equations beside the link rows.
  // (The SGA's own copies: a square model made of an over-determined one
  // has dropped its redundant equations from the model since.)
  for (const SgaRow &row : sga.rows)
    if (row.constraint < 0 && row.residual)
      sys.writtenResiduals.push_back(subst.apply(row.residual));
  pc.report.states = sys.stateSets[0].states;
  pc.report.dof = sga.dof;
  pc.report.systemUnknowns = static_cast<int>(n);
  out = std::move(sys);
  return true;
}

std::unique_ptr<Pass> createSgaSystemPass() {
  return std::make_unique<SgaSystemPass>();
}

} // namespace ldae::passes
