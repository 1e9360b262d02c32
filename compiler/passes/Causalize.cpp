// Pass "causalize": see Causalize.h and docs/causalization.md.
//
// Correctness with several state sets (dynamic state selection): an unknown
// is substituted away only if it is algebraic in every set, holds the same
// node in every set, and the equation that computes it is one every set
// shares. Replacing it by the value that equation gives is then an exact
// rewriting of each set's system, whichever set the run is in.
#include "passes/Causalize.h"
#include "passes/Events.h"
#include "passes/Pass.h"
#include "passes/Passes.h"
#include "passes/Results.h"
#include "passes/SystemStructure.h"

#include "graph/Matching.h"
#include "graph/Scc.h"
#include "ir/Differentiate.h"
#include "ir/Query.h"
#include "ir/Evaluate.h"
#include "ir/Substitute.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <tuple>
#include <unordered_set>

namespace ldae::passes {

const char *causalBlockKindName(CausalBlock::Kind k) {
  switch (k) {
  case CausalBlock::Kind::Explicit:
    return "explicit";
  case CausalBlock::Kind::Derivative:
    return "derivative";
  case CausalBlock::Kind::Nonlinear:
    return "nonlinear";
  case CausalBlock::Kind::Kept:
    return "kept";
  case CausalBlock::Kind::Loop:
    return "loop";
  }
  return "?";
}

namespace {

/// How an equation can be solved for one of its unknowns.
enum class Solvability {
  No,        // not linear in it
  Variable,  // linear, coefficient depends on other unknowns
  Parameter, // linear, coefficient a nonzero constant or parameter expression
};

struct Assignment {
  int row;
  int unknown;
  ir::ExprRef coefficient; // ∂row/∂unknown
};

/// A VarKey as one integer, for hash sets and maps of keys.
uint64_t code(ir::VarKey k) {
  return (static_cast<uint64_t>(k.var) << 16) | k.order;
}

class Causalizer {
public:
  Causalizer(ir::DaeSystem &sys, const SourceManager *sources,
             CausalResult &out)
      : sys_(sys), sources_(sources), out_(out), ctx_(*sys.ctx), diff_(ctx_),
        n_(static_cast<int>(sys.unknowns.size())) {}

  void run();

private:
  ir::VarKey key(int u) const { return sys_.unknowns[u].key; }
  ir::VarKey derivativeKey(int u) const {
    return {key(u).var, key(u).order + 1};
  }
  std::string columnName(int u) const {
    return differential0_[u] ? "der(" + sys_.unknowns[u].name + ")"
                             : sys_.unknowns[u].name;
  }
  SourceLoc rowLoc(int r) const {
    return r < static_cast<int>(sys_.residualLocs.size()) ? sys_.residualLocs[r]
                                                          : SourceLoc{};
  }
  std::string rowWhere(int r) const {
    SourceLoc loc = rowLoc(r);
    if (!loc.valid() || !sources_)
      return "";
    return sources_->path(loc.file) + ":" + std::to_string(loc.line);
  }

  void findEligible();
  /// Whether a coefficient may switch between branches (`if`): only an
  /// assignment of a scalar block takes one; the explicit ODE form and
  /// tearing want a coefficient that holds everywhere.
  enum class Branches { Reject, Allow };
  Solvability solvability(int row, ir::VarKey k, ir::ExprRef *coef,
                          Branches branches = Branches::Reject);
  bool readsSelection(ir::ExprRef e) const;
  /// Whether a coefficient of model parameters only is 0 at their values.
  bool vanishesAtParameters(ir::ExprRef a) const;
  Solvability solvabilityIn(ir::ExprRef r, ir::VarKey k, ir::ExprRef *coef,
                            Branches branches = Branches::Reject);
  bool explicitOdeForm();
  void scalarBlock(int row, int col);
  void loopBlock(const std::vector<int> &rows);
  bool rebuild();

  ir::DaeSystem &sys_;
  const SourceManager *sources_;
  CausalResult &out_;
  ir::ExprContext &ctx_;
  ir::Differentiator diff_;
  const int n_;
  std::vector<bool> differential0_; // set 0
  std::vector<bool> differentialAny_;
  /// Per unknown: why it must keep its slot, or null when it may be
  /// substituted away.
  std::vector<const char *> held_;
  std::vector<char> commonRow_; // residual row shared by every set
  graph::BipartiteGraph graph_;
  graph::Matching matching_;
  bool explicitDerivatives_ = true; // every derivative block is linear in it
  std::vector<Assignment> assignments_; // in solve order
  std::vector<char> rowAssigned_, unknownAssigned_;
};

void Causalizer::findEligible() {
  const size_t nsets = sys_.stateSets.size();
  differential0_ = ir::setDifferential(sys_, 0);
  differentialAny_ = ir::anyDifferential(sys_);
  commonRow_.assign(n_, 1);
  for (size_t s = 1; s < nsets; ++s)
    for (int r = 0; r < n_; ++r)
      if (sys_.stateSets[s].residuals[r] != sys_.stateSets[0].residuals[r])
        commonRow_[r] = 0;
  // Variables read through pre() keep their slot: the value before an
  // event is the slot's.
  std::unordered_set<ir::VarId> readByPre;
  std::vector<ir::ExprRef> roots;
  for (const ir::StateSet &st : sys_.stateSets)
    roots.insert(roots.end(), st.residuals.begin(), st.residuals.end());
  roots.insert(roots.end(), sys_.roots.begin(), sys_.roots.end());
  roots.insert(roots.end(), sys_.initialResiduals.begin(),
               sys_.initialResiduals.end());
  for (ir::ExprRef e : ir::topologicalOrder(roots))
    if (e->kind() == ir::ExprKind::Pre)
      readByPre.insert(e->var());
  held_.assign(n_, nullptr);
  for (int u = 0; u < n_; ++u) {
    const ir::SystemUnknown &su = sys_.unknowns[u];
    if (differentialAny_[u])
      held_[u] = "a state in another candidate state set";
    else if (su.fixed)
      held_[u] = "fixed = true";
    else if (readByPre.count(su.key.var))
      held_[u] = "read by pre()";
    for (const ir::StateSet &st : sys_.stateSets)
      if (!held_[u] && !st.keys.empty() && st.keys[u] != su.key)
        held_[u] = "its slot changes meaning between candidate state sets";
  }
}

bool Causalizer::readsSelection(ir::ExprRef e) const {
  if (sys_.dynamicSets.empty())
    return false;
  const ir::ParamId first = sys_.dynamicSets.front().param;
  for (ir::ExprRef x :
       ir::topologicalOrder(std::span<const ir::ExprRef>(&e, 1)))
    if (x->kind() == ir::ExprKind::Parameter && x->param() >= first &&
        x->param() < first + sys_.selectionCount)
      return true;
  return false;
}

Solvability Causalizer::solvability(int row, ir::VarKey k, ir::ExprRef *coef,
                                     Branches branches) {
  return solvabilityIn(sys_.stateSets[0].residuals[row], k, coef, branches);
}

Solvability Causalizer::solvabilityIn(ir::ExprRef r, ir::VarKey k,
                                      ir::ExprRef *coef, Branches branches) {
  ir::ExprRef a = diff_.partial(r, k);
  if (a->isConstant(0) || ir::dependsOn(a, k))
    return Solvability::No;
  if (branches == Branches::Reject) {
    for (ir::ExprRef e :
         ir::topologicalOrder(std::span<const ir::ExprRef>(&a, 1)))
      if (e->kind() == ir::ExprKind::If)
        return Solvability::No;
  } else {
    // x := -row(x = 0) / coefficient is right in every branch as long as
    // no condition reads x: x = 0 would then pick another branch. Such a
    // coefficient switches with a discrete value (the MSL ideal diode's
    // `s * (if off then 1 else Ron)`) or a parameter; kept as an iteration
    // variable instead, its 1/Ron gain put an error-test storm on IDA
    // (docs/causalization.md).
    for (ir::ExprRef e :
         ir::topologicalOrder(std::span<const ir::ExprRef>(&r, 1)))
      if (e->kind() == ir::ExprKind::If && ir::dependsOn(e->operand(0), k))
        return Solvability::No;
  }
  // A run-time selection matrix entry (dynamic state selection) is 0 or 1
  // and changes during the run: never divide by it.
  if (readsSelection(a))
    return Solvability::No;
  // A coefficient of parameters that is 0 at their values: the equation
  // does not read the unknown there (MSL's Translational Vehicle sets its
  // wheels' J = 0 in J*a = tau: dividing by it was a domain error at the
  // start). Kept for the integrator, the equation holds for any value.
  if (vanishesAtParameters(a))
    return Solvability::No;
  *coef = a;
  if (variablesOf(a).empty() && !ir::dependsOnTime(a))
    return Solvability::Parameter;
  return Solvability::Variable;
}

bool Causalizer::vanishesAtParameters(ir::ExprRef a) const {
  if (!variablesOf(a).empty() || ir::dependsOnTime(a))
    return false;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  bool modelParameters = true;
  ir::EvalEnv env;
  env.variable = [&](ir::VarKey) { return nan; };
  env.parameter = [&](ir::ParamId q) {
    if (q < sys_.parameterValues.size())
      return sys_.parameterValues[q];
    modelParameters = false; // a discrete value: known only at run time
    return nan;
  };
  Expected<double> v = ir::evaluate(a, env);
  return modelParameters && v && *v == 0;
}

void Causalizer::scalarBlock(int row, int col) {
  CausalBlock b;
  b.variables.push_back(columnName(col));
  b.equations.push_back(rowWhere(row));
  ir::ExprRef coef = nullptr;
  if (differential0_[col]) {
    b.kind = CausalBlock::Kind::Derivative;
    b.iteration.push_back(columnName(col));
    b.residuals = 1;
    if (solvability(row, derivativeKey(col), &coef) == Solvability::No)
      explicitDerivatives_ = false;
  } else if (solvability(row, key(col), &coef, Branches::Allow) ==
             Solvability::No) {
    b.kind = CausalBlock::Kind::Nonlinear;
    b.iteration.push_back(columnName(col));
    b.residuals = 1;
  } else if (held_[col] || !commonRow_[row]) {
    // An equation that could compute it; say why the integrator keeps it.
    b.kind = CausalBlock::Kind::Kept;
    b.iteration.push_back(columnName(col));
    b.residuals = 1;
    b.reason = held_[col] ? held_[col]
                          : "its equation differs between candidate state sets";
  } else {
    // The coefficient is this block's whole Jacobian: where it vanishes
    // the equation does not determine the variable at all.
    b.kind = CausalBlock::Kind::Explicit;
    assignments_.push_back({row, col, coef});
    rowAssigned_[row] = unknownAssigned_[col] = 1;
  }
  out_.blocks.push_back(std::move(b));
}

// Greedy tearing: repeatedly assign an equation left with one unknown of the
// loop that it solves with a coefficient that cannot vanish; when none is
// left, make the unknown that the most unsolved equations read an iteration
// variable (ties: a stateSelect hint, then a user-given start value, then
// canonical order). State derivatives of the loop are the integrator's from
// the start.
void Causalizer::loopBlock(const std::vector<int> &rows) {
  CausalBlock b;
  b.kind = CausalBlock::Kind::Loop;
  // The block's columns are those matched to its rows; the other columns
  // its rows read belong to earlier blocks.
  std::vector<int> cols;
  for (int r : rows) {
    b.equations.push_back(rowWhere(r));
    cols.push_back(matching_.rowMate[r]);
  }
  std::sort(cols.begin(), cols.end());
  for (int c : cols)
    b.variables.push_back(columnName(c));

  std::unordered_map<int, int> local; // column -> index in cols
  for (size_t i = 0; i < cols.size(); ++i)
    local[cols[i]] = static_cast<int>(i);
  const size_t nr = rows.size(), nc = cols.size();
  std::vector<std::vector<int>> rowCols(nr), colRows(nc);
  for (size_t i = 0; i < nr; ++i)
    for (int c : graph_.rows[rows[i]])
      if (auto it = local.find(c); it != local.end()) {
        rowCols[i].push_back(it->second);
        colRows[it->second].push_back(static_cast<int>(i));
      }
  std::vector<char> known(nc, 0), solved(nr, 0);
  std::vector<int> unknownCount(nr), readers(nc);
  for (size_t i = 0; i < nr; ++i)
    unknownCount[i] = static_cast<int>(rowCols[i].size());
  for (size_t j = 0; j < nc; ++j)
    readers[j] = static_cast<int>(colRows[j].size());

  std::vector<int> ready; // rows with one unknown left
  auto makeKnown = [&](int j) {
    known[j] = 1;
    for (int i : colRows[j])
      if (!solved[i] && --unknownCount[i] == 1)
        ready.push_back(i);
  };
  std::vector<int> iteration;
  auto tear = [&](int j) {
    iteration.push_back(j);
    b.iteration.push_back(columnName(cols[j]));
    makeKnown(j);
  };
  for (size_t j = 0; j < nc; ++j)
    if (differential0_[cols[j]] || held_[cols[j]])
      tear(static_cast<int>(j));
  for (size_t i = 0; i < nr; ++i)
    if (unknownCount[i] == 1)
      ready.push_back(static_cast<int>(i));

  auto hint = [&](int j) {
    const ir::VarKey k = key(cols[j]);
    if (!sys_.model || k.order != 0 || k.var >= sys_.model->variables.size())
      return std::make_pair(1, 0);
    const ir::Variable &v = sys_.model->variables[k.var];
    int pref = v.stateSelect == ir::StateSelect::Prefer ||
                       v.stateSelect == ir::StateSelect::Always
                   ? 2
               : v.stateSelect == ir::StateSelect::Avoid ||
                       v.stateSelect == ir::StateSelect::Never
                   ? 0
                   : 1;
    return std::make_pair(pref, v.hasStart ? 1 : 0);
  };
  using Candidate = std::tuple<int, int, int, int, int>; // hint, readers, start, -j, j
  std::priority_queue<Candidate> candidates;
  for (size_t j = 0; j < nc; ++j)
    if (!known[j]) {
      auto [pref, start] = hint(static_cast<int>(j));
      candidates.emplace(pref, readers[j], start, -static_cast<int>(j),
                         static_cast<int>(j));
    }
  size_t assigned = 0, knownCount = iteration.size();
  while (knownCount + assigned < nc) {
    bool progress = false;
    while (!ready.empty()) {
      int i = ready.back();
      ready.pop_back();
      if (solved[i] || unknownCount[i] != 1 || !commonRow_[rows[i]])
        continue;
      int j = -1;
      for (int c : rowCols[i])
        if (!known[c])
          j = c;
      if (j < 0)
        continue;
      ir::ExprRef coef = nullptr;
      if (solvability(rows[i], key(cols[j]), &coef) != Solvability::Parameter)
        continue;
      solved[i] = 1;
      assignments_.push_back({rows[i], cols[j], coef});
      rowAssigned_[rows[i]] = unknownAssigned_[cols[j]] = 1;
      ++assigned;
      for (int c : rowCols[i])
        --readers[c];
      makeKnown(j);
      progress = true;
    }
    if (progress || knownCount + assigned >= nc)
      continue;
    // Nothing solves explicitly: tear the best remaining candidate.
    while (!candidates.empty()) {
      auto [pref, count, start, negj, j] = candidates.top();
      candidates.pop();
      if (known[j])
        continue;
      if (count != readers[j]) {
        candidates.emplace(pref, readers[j], start, negj, j);
        continue;
      }
      tear(j);
      ++knownCount;
      break;
    }
  }
  b.residuals = static_cast<int>(nr - assigned);
  ++out_.tornLoops;
  out_.blocks.push_back(std::move(b));
}

void Causalizer::run() {
  findEligible();
  SystemReads reads = systemReads(sys_, 0);
  graph_ = systemGraph(sys_, 0, reads, true);
  matching_ = graph::maximumMatching(graph_);
  if (matching_.size < n_)
    return; // not index 1 as built (`--method raw`): nothing to order
  rowAssigned_.assign(n_, 0);
  unknownAssigned_.assign(n_, 0);
  for (const std::vector<int> &blk : graph::bltBlocks(graph_, matching_)) {
    if (blk.size() == 1)
      scalarBlock(blk[0], matching_.rowMate[blk[0]]);
    else
      loopBlock(blk);
  }
  if (!rebuild()) {
    out_.blocks.clear();
    out_.tornLoops = 0;
    return;
  }
  out_.applied = true;
  out_.explicitCount = static_cast<int>(assignments_.size());
  bool ode = explicitDerivatives_ && sys_.stateSets.size() == 1;
  for (const CausalBlock &b : out_.blocks)
    ode = ode && (b.kind == CausalBlock::Kind::Explicit ||
                  b.kind == CausalBlock::Kind::Derivative);
  out_.ode = ode && explicitOdeForm();
  // A linearly implicit system is integrated as the SGA's field whatever
  // its rows look like: it keeps its form (and gets no explicit_ode).
  if (sys_.form != ir::SystemForm::LinearlyImplicit)
    sys_.form =
        out_.ode ? ir::SystemForm::ExplicitOde : ir::SystemForm::Implicit;
}

// The form CVODE takes (ldae_model::explicit_ode): row i is der(x_i) -
// f_i(t, x). Each row must read one derivative, its own unknown's, through
// a coefficient free of derivatives and branches; then the row is divided
// by it and moved to its unknown's place. A value substituted in may read
// another derivative (y = der(x) + 1 in der(z) = y): the form stays a DAE.
bool Causalizer::explicitOdeForm() {
  const int n = static_cast<int>(sys_.unknowns.size());
  std::unordered_map<uint64_t, int> derivativeOf;
  for (int u = 0; u < n; ++u)
    derivativeOf[code(derivativeKey(u))] = u;
  ir::StateSet &st = sys_.stateSets[0];
  std::vector<ir::ExprRef> rows(n, nullptr);
  std::vector<SourceLoc> locs(n);
  for (int r = 0; r < n; ++r) {
    ir::ExprRef res = st.residuals[r];
    int u = -1;
    for (ir::VarKey k : variablesOf(res))
      if (auto it = derivativeOf.find(code(k)); it != derivativeOf.end()) {
        if (u >= 0 && u != it->second)
          return false;
        u = it->second;
      }
    if (u < 0 || rows[u])
      return false;
    ir::ExprRef a = nullptr;
    ir::VarKey dk = derivativeKey(u);
    if (solvabilityIn(res, dk, &a) == Solvability::No)
      return false;
    for (ir::VarKey k : variablesOf(a))
      if (derivativeOf.count(code(k)))
        return false;
    if (a->isConstant(1)) {
      rows[u] = res;
    } else {
      ir::Substitution atZero(ctx_);
      atZero.set(ctx_.var(dk), ctx_.zero());
      rows[u] = ctx_.add(ctx_.var(dk), ctx_.div(atZero.apply(res), a));
    }
    locs[u] = rowLoc(r);
  }
  st.residuals = std::move(rows);
  if (!sys_.residualLocs.empty())
    sys_.residualLocs = std::move(locs);
  return true;
}

// Substitutes the assigned unknowns away, in solve order: each value reads
// only unknowns solved before it, already replaced by their values, so one
// memo serves the whole system and a chain of assignments costs linear time.
bool Causalizer::rebuild() {
  ir::Substitution subst(ctx_);
  std::unordered_set<uint64_t> removed;
  const ir::StateSet &set0 = sys_.stateSets[0];
  for (const Assignment &a : assignments_) {
    ir::VarKey k = key(a.unknown);
    ir::ExprRef x = ctx_.var(k);
    ir::Substitution atZero(ctx_);
    atZero.set(x, ctx_.zero());
    // row = coefficient * x + rest, so x = -rest / coefficient.
    ir::ExprRef rest = atZero.apply(set0.residuals[a.row]);
    ir::ExprRef value = ctx_.div(ctx_.neg(rest), a.coefficient);
    subst.extend(x, subst.apply(value));
    removed.insert(code(k));
  }
  if (assignments_.empty())
    return true;

  std::vector<int> keepUnknown, keepRow;
  for (int u = 0; u < n_; ++u)
    if (!unknownAssigned_[u])
      keepUnknown.push_back(u);
  for (int r = 0; r < n_; ++r)
    if (!rowAssigned_[r])
      keepRow.push_back(r);

  ir::DaeSystem next = sys_;
  next.unknowns.clear();
  for (int u : keepUnknown)
    next.unknowns.push_back(sys_.unknowns[u]);
  next.residualLocs.clear();
  for (int r : keepRow)
    next.residualLocs.push_back(rowLoc(r));
  for (size_t s = 0; s < sys_.stateSets.size(); ++s) {
    const ir::StateSet &old = sys_.stateSets[s];
    ir::StateSet &st = next.stateSets[s];
    st.residuals.clear();
    for (int r : keepRow)
      st.residuals.push_back(subst.apply(old.residuals[r]));
    st.differential.clear();
    for (int u : keepUnknown)
      st.differential.push_back(old.differential[u]);
    if (!old.keys.empty()) {
      st.keys.clear();
      for (int u : keepUnknown)
        st.keys.push_back(old.keys[u]);
    }
    for (ir::ExprRef &e : st.pivot)
      e = subst.apply(e);
  }
  for (ir::DynamicStateSet &ds : next.dynamicSets) {
    for (ir::ExprRef &e : ds.jacobian)
      e = subst.apply(e);
    for (ir::ExprRef &e : ds.values)
      e = subst.apply(e);
  }
  next.tested.clear();
  for (const Assignment &a : assignments_)
    next.tested.push_back({subst.apply(ctx_.var(key(a.unknown))),
                           sys_.unknowns[a.unknown].nominal});
  for (ir::ExprRef &e : next.initialResiduals)
    e = subst.apply(e);
  for (ir::ExprRef &e : next.constraints)
    e = subst.apply(e);
  for (ir::ExprRef &e : next.roots)
    e = subst.apply(e);
  const std::vector<ir::ExprRef> updateBefore = next.events.update;
  ir::forEachEventExpr(next.events,
                       [&](ir::ExprRef &e) { e = subst.apply(e); });
  readUpdatedThroughSolved(next, updateBefore);
  std::vector<int> newIndex(n_, -1);
  for (size_t i = 0; i < keepUnknown.size(); ++i)
    newIndex[keepUnknown[i]] = static_cast<int>(i);
  if (!ir::renumberReinits(next.events, newIndex))
    return false;
  std::unordered_map<uint64_t, int> assignedRow;
  for (const Assignment &a : assignments_)
    assignedRow[code(key(a.unknown))] = a.row;
  for (ir::SystemOutput &o : next.outputs) {
    if (o.value->kind() == ir::ExprKind::Variable)
      if (auto it = assignedRow.find(code(o.value->varKey()));
          it != assignedRow.end())
        o.loc = rowLoc(it->second);
    o.value = subst.apply(o.value);
  }

  // Nothing may still read a removed unknown (it has no slot any more).
  std::vector<ir::ExprRef> all(next.initialResiduals);
  all.insert(all.end(), next.constraints.begin(), next.constraints.end());
  all.insert(all.end(), next.roots.begin(), next.roots.end());
  for (ir::ExprRef e : ir::eventExprs(next.events))
    all.push_back(e);
  for (const ir::SystemOutput &o : next.outputs)
    all.push_back(o.value);
  for (const ir::TestedValue &v : next.tested)
    all.push_back(v.value);
  for (const ir::StateSet &st : next.stateSets) {
    all.insert(all.end(), st.residuals.begin(), st.residuals.end());
    all.insert(all.end(), st.pivot.begin(), st.pivot.end());
  }
  for (const ir::DynamicStateSet &ds : next.dynamicSets) {
    all.insert(all.end(), ds.jacobian.begin(), ds.jacobian.end());
    all.insert(all.end(), ds.values.begin(), ds.values.end());
  }
  for (ir::ExprRef e : ir::topologicalOrder(all))
    if (e->kind() == ir::ExprKind::Variable && removed.count(code(e->varKey())))
      return false;
  sys_ = std::move(next);
  return true;
}

} // namespace

void causalize(ir::DaeSystem &sys, const CausalizeOptions &opts,
               CausalResult &out) {
  out = CausalResult{};
  out.unknownsBefore = static_cast<int>(sys.unknowns.size());
  if (opts.enabled && !sys.unknowns.empty())
    Causalizer(sys, opts.sources, out).run();
  out.integratorUnknowns.clear();
  std::vector<bool> diff = ir::setDifferential(sys, 0);
  for (size_t u = 0; u < sys.unknowns.size(); ++u) {
    out.integratorUnknowns.push_back(sys.unknowns[u].name);
    out.iterationVariables += diff[u] ? 0 : 1;
  }
}

} // namespace ldae::passes

namespace ldae::passes {

namespace {

/// "causalize": the system in causal form; the report gets its blocks.
/// The BLT result describes the system before, so it is made again.
class CausalizePass
    : public TypedPass<CausalizePass, Reads<>, Updates<ir::DaeSystem, BltResult>,
                       Produces<CausalResult>> {
public:
  CausalizePass() : TypedPass(PassId::Causalize) {}
  bool runOn(PassContext &ctx, ir::DaeSystem &sys, BltResult &blt,
             CausalResult &out) {
    CausalizeOptions opts;
    opts.enabled = ctx.opts.causalize && !ctx.jumpsMatter;
    opts.sources = &ctx.diags.sources();
    causalize(sys, opts, out);
    ctx.report.causal = out;
    return !out.applied || bltOrder(ctx, sys, false, blt);
  }
};

} // namespace

std::unique_ptr<Pass> createCausalizePass() {
  return std::make_unique<CausalizePass>();
}

} // namespace ldae::passes
