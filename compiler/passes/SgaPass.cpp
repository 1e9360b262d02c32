// Pass "sga": runs the geometric algorithm (Sga.h) on the model after
// alias elimination and gives its verdict before structural analysis
// does: a model whose solution is not unique or that has none stops here
// with the reason (the free functions and what they move, or the
// constraint that cannot hold and where it came from); equations the
// others imply are named and left out, so an over-determined but
// consistent model (a mechanism with a redundant loop) goes on square.
// Pass "sga-check" compares the SGA's degrees of freedom with the states
// structural index reduction chose: where they differ, structure was
// fooled (cancellation, a singular derivative matrix) and the SGA's count
// stands in the report.
#include "passes/Events.h"
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/Sga.h"

#include "ir/Evaluate.h"
#include "ir/Print.h"
#include "ir/Query.h"

#include <cmath>
#include <cstdio>

#include <algorithm>

namespace ldae::passes {

namespace {

constexpr size_t kMaxNotes = 8;

std::vector<std::string> equationTexts(PassContext &ctx,
                                       const std::vector<int> &eqs) {
  std::vector<std::string> out;
  for (int e : eqs)
    out.push_back(ctx.equationText(e));
  return out;
}

void noteEquations(PassContext &ctx, Diagnostic &d, const std::vector<int> &eqs) {
  for (size_t i = 0; i < eqs.size() && i < kMaxNotes; ++i)
    DiagnosticEngine::addNote(d, ctx.model.equations[eqs[i]].loc,
                              DiagId::NoteEquationInvolved,
                              {ctx.equationText(eqs[i])});
}

/// "the equation at a.lsd:7" / "the equations at a.lsd:7, a.lsd:9".
std::string describeEquations(PassContext &ctx, const std::vector<int> &eqs) {
  std::vector<std::string> where;
  for (int e : eqs) {
    std::string w = ctx.where(ctx.model.equations[e].loc);
    where.push_back(w.empty() ? "'" + ctx.equationText(e) + "'" : w);
  }
  std::string list;
  for (size_t i = 0; i < where.size(); ++i)
    list += (i == 0 ? "" : i + 1 == where.size() ? " and " : ", ") + where[i];
  return (eqs.size() == 1 ? "the equation at " : "the equations at ") + list;
}

SgaReport toReport(PassContext &ctx, const SgaResult &r) {
  const ir::Model &m = ctx.model;
  SgaReport rep;
  rep.outcome = r.outcome;
  rep.dof = r.dof;
  rep.freeFunctions = r.freeFunctions;
  rep.steps = r.steps;
  rep.generations.resize(static_cast<size_t>(r.generations));
  for (const SgaConstraintExpr &c : r.constraints) {
    if (c.generation >= r.generations)
      rep.generations.resize(static_cast<size_t>(c.generation) + 1);
    rep.generations[static_cast<size_t>(c.generation)].push_back(
        {ir::printLsd(c.expr, &m), equationTexts(ctx, c.sources)});
  }
  for (int c : r.freeColumns)
    rep.undetermined.push_back(
        m.variables[r.form.columns[static_cast<size_t>(c)].var].name);
  rep.redundant = equationTexts(ctx, r.redundant);
  for (const std::string &text : equationTexts(ctx, r.implied))
    rep.redundant.push_back(text);
  if (r.conflict >= 0) {
    const SgaConstraintExpr &c = r.constraints[static_cast<size_t>(r.conflict)];
    rep.conflict = SgaConstraint{ir::printLsd(c.expr, &m),
                                 equationTexts(ctx, c.sources)};
  }
  if (r.outcome == SgaReport::Outcome::Unique && r.dof == 0)
    for (size_t i = 0; i < r.form.slots.size(); ++i)
      rep.point.emplace_back(m.variableName(r.form.slots[i]), r.point[i]);
  return rep;
}

/// Leaves the equations `drop` out of the model, renumbering the SGA's
/// references to the others.
void dropEquations(ir::Model &m, SgaResult &sga, const std::vector<int> &drop) {
  std::vector<int> renumber(m.equations.size(), -1);
  std::vector<ir::Equation> keep;
  for (size_t e = 0; e < m.equations.size(); ++e) {
    if (std::find(drop.begin(), drop.end(), static_cast<int>(e)) != drop.end())
      continue;
    renumber[e] = static_cast<int>(keep.size());
    keep.push_back(std::move(m.equations[e]));
  }
  m.equations = std::move(keep);
  auto apply = [&](std::vector<int> &sources) {
    std::vector<int> out;
    for (int e : sources)
      if (renumber[static_cast<size_t>(e)] >= 0)
        out.push_back(renumber[static_cast<size_t>(e)]);
    sources = std::move(out);
  };
  for (SgaConstraintExpr &c : sga.constraints)
    apply(c.sources);
  for (SgaRow &r : sga.rows)
    apply(r.sources);
  sga.redundant.clear();
}

/// A zero-dimensional P_f is one point: a fixed start value elsewhere can
/// never hold.
bool checkFixedOnPoint(PassContext &ctx, const SgaResult &r) {
  const ir::Model &m = ctx.model;
  // Constraints that read time make P_f a point at each time, moving with
  // it (a capacitor tied to a sine source): the point found is at some
  // random time, and the start's consistency is the initialization's to
  // judge at the start time.
  for (const SgaConstraintExpr &c : r.constraints)
    if (ir::dependsOnTime(c.expr))
      return true;
  // Ten digits: the point is found by Gauss-Newton, its last bits are noise.
  auto digits = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return std::string(buf);
  };
  std::string where;
  for (size_t i = 0; i < r.form.slots.size(); ++i)
    where += (i ? ", " : "") + m.variableName(r.form.slots[i]) + " = " +
             digits(r.point[i]);
  for (size_t i = 0; i < r.form.slots.size(); ++i) {
    ir::VarKey k = r.form.slots[i];
    const ir::Variable &v = m.variables[k.var];
    if (k.order != 0 || !v.fixed)
      continue;
    if (std::abs(v.start - r.point[i]) <= 1e-8 * std::max(1.0, std::abs(r.point[i])))
      continue;
    ctx.diags.report(DiagId::ErrSgaFixedOffPoint, v.loc,
                     {v.name, ir::printNumber(v.start), "(" + where + ")"});
    return false;
  }
  return true;
}

/// A model with no unknowns (`0 = 1`, `der(p) = p` of a parameter, a size
/// parameter set to 0) has no manifold to sample: each equation holds at
/// the parameter values or the model has no solution.
bool equationsWithoutUnknownsHold(PassContext &ctx, SgaResult &out) {
  ir::Model &m = ctx.model;
  ir::EvalEnv env = ctx.startEnv();
  std::vector<int> all;
  for (size_t e = 0; e < m.equations.size(); ++e) {
    all.push_back(static_cast<int>(e));
    Expected<double> r = ir::evaluate(m.equations[e].residual, env, &m);
    if (r && std::fabs(*r) <= 1e-12)
      continue;
    ctx.diags.report(DiagId::ErrSgaNoSolution, m.equations[e].loc,
                     {ir::printLsd(m.equations[e].residual, &m),
                      describeEquations(ctx, {all.back()})});
    return false;
  }
  out.skipped = "the model has no unknowns";
  if (!all.empty()) {
    Diagnostic &d = ctx.diags.report(
        DiagId::WarnSgaRedundant, m.equations.front().loc,
        {describeEquations(ctx, all), all.size() == 1 ? "it" : "them"});
    noteEquations(ctx, d, all);
    dropEquations(m, out, all);
  }
  return true;
}

class SgaPass : public TypedPass<SgaPass, Reads<EventResult>, Updates<>,
                                 Produces<SgaResult, ir::DaeSystem>> {
public:
  explicit SgaPass(bool always) : TypedPass(PassId::Sga), always_(always) {}
  bool runOn(PassContext &ctx, const EventResult &ev, SgaResult &out,
             ir::DaeSystem &sys);

private:
  bool always_; // the sga and ode methods: no size limit
};

bool SgaPass::runOn(PassContext &ctx, const EventResult &ev, SgaResult &out,
                    ir::DaeSystem &sys) {
  out.input = sgaInput(ctx.model);
  if (out.input.unknowns.empty()) {
    bool ok = equationsWithoutUnknownsHold(ctx, out);
    ctx.report.sgaNote = out.skipped;
    return ok;
  }
  // The sampling evaluates the equations at points a run never reaches,
  // and C code may not survive them: MSL's CombiTimeTable read before its
  // first getNextTimeEvent indexes an interval table it has not built
  // (Interaction1 crashed in getValue).
  if (std::string c = externalOfUnknowns(ctx.model); !c.empty()) {
    out.skipped = "the model calls the external function '" + c +
                  "' at values of its unknowns, and C code is called only at "
                  "points a run reaches";
    ctx.report.sgaNote = out.skipped;
    return true;
  }
  size_t slots = 0;
  for (int o : out.input.originalOrder)
    slots += static_cast<size_t>(std::max(1, o));
  if (!always_ && slots > kSgaCrossCheckLimit) {
    out.skipped = "the model has " + std::to_string(slots) +
                  " coordinates, above the cross-check's limit of " +
                  std::to_string(kSgaCrossCheckLimit);
    ctx.report.sgaNote = out.skipped;
    return true;
  }
  runSga(ctx, out);
  if (!out.ran) {
    ctx.report.sgaNote = out.skipped;
    return true;
  }
  ctx.report.sga = toReport(ctx, out);
  // The differentiation index is the number of constraint generations:
  // each was found by differentiating the one before (docs/indices.md).
  if (out.outcome == SgaReport::Outcome::Unique)
    ctx.report.differentiationIndex = out.generations;
  ir::Model &m = ctx.model;
  switch (out.outcome) {
  case SgaReport::Outcome::NoSolution: {
    if (out.conflict < 0 ||
        static_cast<size_t>(out.conflict) >= out.constraints.size())
      return true; // no conflict to name: no verdict (runSga's contract)
    const SgaConstraintExpr &c =
        out.constraints[static_cast<size_t>(out.conflict)];
    // Relations of the unknowns frozen in one branch at the sampled point
    // (MSL's NandGate: its transistors' regions) can show the SGA a
    // conflict no branch has: structure's system runs, and a model that
    // truly has none stops at its initialization, located. The sga and
    // ode methods, which integrate the SGA's field, stop here.
    bool piecewise = !always_ && !ev.roots.empty();
    Diagnostic &d = ctx.diags.report(
        piecewise ? DiagId::WarnSgaNoSolutionPiecewise
                  : DiagId::ErrSgaNoSolution,
        m.equations[c.sources.front()].loc,
        {ir::printLsd(c.expr, &m), describeEquations(ctx, c.sources)});
    // And the equations of the constraints it contradicts (those sharing
    // a variable with it).
    std::vector<int> also = c.sources;
    std::vector<ir::VarKey> vars = ir::freeVariables(c.expr);
    for (const SgaConstraintExpr &k : out.constraints) {
      if (&k == &c)
        continue;
      for (ir::VarKey v : ir::freeVariables(k.expr))
        if (std::find(vars.begin(), vars.end(), v) != vars.end()) {
          for (int e : k.sources)
            if (std::find(also.begin(), also.end(), e) == also.end())
              also.push_back(e);
          break;
        }
    }
    noteEquations(ctx, d, also);
    return piecewise;
  }
  case SgaReport::Outcome::NotUnique: {
    std::vector<std::string> names = ctx.report.sga->undetermined;
    Diagnostic &d = ctx.diags.report(
        DiagId::ErrSgaNotUnique,
        names.empty() ? m.loc
                      : m.variables[out.form.columns[out.freeColumns[0]].var].loc,
        {std::to_string(out.freeFunctions), quotedList(names)});
    for (size_t i = 0; i < out.freeColumns.size() && i < kMaxNotes; ++i) {
      ir::VarId v = out.form.columns[static_cast<size_t>(out.freeColumns[i])].var;
      DiagnosticEngine::addNote(d, m.variables[v].loc,
                                DiagId::NoteVariableDeclared,
                                {m.variables[v].name});
    }
    return false;
  }
  case SgaReport::Outcome::Unique:
    break;
  }
  if (out.dof == 0 && !checkFixedOnPoint(ctx, out))
    return false;
  if (!out.redundant.empty()) {
    Diagnostic &d = ctx.diags.report(
        DiagId::WarnSgaRedundant, m.equations[out.redundant.front()].loc,
        {describeEquations(ctx, out.redundant),
         out.redundant.size() == 1 ? "it" : "them"});
    noteEquations(ctx, d, out.redundant);
    // The sga and ode methods keep them: their vector field picks
    // independent rows by itself.
    if (!always_)
      dropEquations(m, out, out.redundant);
  }
  if (!always_ && m.equations.size() > out.input.unknowns.size()) {
    // Consistent but over-determined (a hidden constraint written out):
    // index reduction needs a square system, the SGA's vector field on
    // P_f does not.
    Diagnostic &d = ctx.diags.report(
        DiagId::WarnSgaOverDetermined,
        out.implied.empty() ? m.loc : m.equations[out.implied.front()].loc,
        {std::to_string(m.equations.size()),
         std::to_string(out.input.unknowns.size()),
         out.implied.empty() ? std::string("the extra equations are")
                             : describeEquations(ctx, out.implied) +
                                   (out.implied.size() == 1 ? " is" : " are")});
    noteEquations(ctx, d, out.implied);
    if (!buildSgaSystem(ctx, out, /*project=*/true, sys))
      return false;
    ctx.finished = true;
  }
  return true;
}

class SgaCheckPass
    : public TypedPass<SgaCheckPass, Reads<SgaResult>,
                       Updates<ir::DaeSystem>, Produces<>> {
public:
  SgaCheckPass() : TypedPass(PassId::SgaCheck) {}
  bool runOn(PassContext &ctx, const SgaResult &sga, ir::DaeSystem &sys);
};

bool SgaCheckPass::runOn(PassContext &ctx, const SgaResult &sga,
                         ir::DaeSystem &sys) {
  if (!sga.ran || sga.outcome != SgaReport::Outcome::Unique)
    return true;
  const int structural = ctx.report.dof;
  if (structural == sga.dof)
    return true;
  // The equations behind the constraints structure did not see.
  std::vector<int> eqs;
  for (const SgaConstraintExpr &c : sga.constraints)
    for (int e : c.sources)
      if (std::find(eqs.begin(), eqs.end(), e) == eqs.end())
        eqs.push_back(e);
  // Relations of the unknowns choose branches of the equations; the SGA
  // samples its ranks with them frozen, and a badly scaled branch (a slew
  // limiter's 1/Td = 1e4) can make it see a constraint that is not there.
  // Structure sees every branch at once: its system runs (should it be
  // singular in a branch, the run stops there, located).
  if (!sys.roots.empty()) {
    Diagnostic &d = ctx.diags.report(
        DiagId::WarnSgaPiecewise,
        eqs.empty() ? ctx.model.loc : ctx.model.equations[eqs.front()].loc,
        {std::to_string(structural), std::to_string(sga.dof)});
    noteEquations(ctx, d, eqs);
    return true;
  }
  std::string why =
      structural > sga.dof
          ? "the derivatives the model's equations contain are dependent "
            "(a singular derivative matrix or a cancellation), so " +
                std::to_string(structural - sga.dof) +
                " more constraint(s) hold than structure sees"
          : "structure finds constraints the equations do not impose";
  why += "; the SGA's vector field on P_f is integrated instead (as "
         "--method sga)";
  Diagnostic &d = ctx.diags.report(
      DiagId::WarnSgaStructureFooled,
      eqs.empty() ? ctx.model.loc : ctx.model.equations[eqs.front()].loc,
      {std::to_string(structural), std::to_string(sga.dof), why});
  noteEquations(ctx, d, eqs);
  ctx.report.structuralDof = structural;
  // The SGA's vector field on P_f is what runs: the index-1 system
  // structure built would start off P_f or stall on the singularity.
  if (!buildSgaSystem(ctx, sga, /*project=*/true, sys))
    return false;
  ctx.report.dof = sga.dof;
  ctx.finished = true;
  return true;
}

} // namespace

std::unique_ptr<Pass> createSgaPass(bool always) {
  return std::make_unique<SgaPass>(always);
}

std::unique_ptr<Pass> createSgaCheckPass() {
  return std::make_unique<SgaCheckPass>();
}

} // namespace ldae::passes
