// Pass "events": discrete variables, relations, when-clauses, reinit,
// sample, initial(), terminal(), assert out of the continuous system into
// the discrete state and its event update (Events.h, docs/events.md).
//
// Every discrete value is defined by an expression D over the continuous
// point (Variable nodes, time), pre() values and the *new* values of other
// discrete values (read as their current Parameter). The update inlines
// those in dependency order, so it is one expression per value over
// (t, y, y', pre): what ldae_model::event_update computes.
#include "passes/Events.h"

#include "passes/DiscreteInitialization.h"

#include "passes/Passes.h"
#include "passes/Results.h"

#include "graph/Matching.h"
#include "ir/Discrete.h"
#include "ir/Evaluate.h"
#include "ir/Query.h"
#include "ir/Substitute.h"
#include "ir/Traverse.h"

#include <algorithm>
#include <map>
#include <set>

namespace ldae::passes {

namespace {

/// A slot of the discrete state while the pass builds it.
struct Slot {
  ir::DiscreteKind kind = ir::DiscreteKind::Variable;
  std::string name;
  ir::ExprRef node = nullptr; // Variable: var(v); Relation: the Compare
  ir::VarId var = 0;          // Variable and the inputs
  int when = -1;              // When: the clause
  ir::ExprRef condition = nullptr; // When: its (element of the) condition
  bool timeRelation = false;
  ir::ExprRef threshold = nullptr; // time relation: the other side
  ir::CompareKind timeCompare = ir::CompareKind::Lt; // time <op> threshold
  /// Delay: the delayed expression as the integrator reads the discrete
  /// values (their current and pre() Parameters, relations frozen), with
  /// the variables that change at events only replaced by their values.
  ir::ExprRef delayed = nullptr;
};

ir::DiscreteKind inputKind(ir::EventInput in) {
  switch (in) {
  case ir::EventInput::Initial:
    return ir::DiscreteKind::Initial;
  case ir::EventInput::Terminal:
    return ir::DiscreteKind::Terminal;
  case ir::EventInput::Sample:
    return ir::DiscreteKind::Sample;
  case ir::EventInput::Delay:
    return ir::DiscreteKind::Delay;
  case ir::EventInput::None:
    break;
  }
  return ir::DiscreteKind::Variable;
}

/// The conditions a clause watches: each element of a vector condition.
std::span<const ir::ExprRef> conditionsOf(const ir::WhenClause &w) {
  if (w.elements.empty())
    return {&w.condition, 1};
  return w.elements;
}

bool isInput(ir::DiscreteKind k) {
  return k == ir::DiscreteKind::Initial || k == ir::DiscreteKind::Terminal ||
         k == ir::DiscreteKind::Sample;
}

/// `a <c> b` read as `b <c'> a`.
ir::CompareKind mirrored(ir::CompareKind c) {
  switch (c) {
  case ir::CompareKind::Lt:
    return ir::CompareKind::Gt;
  case ir::CompareKind::Le:
    return ir::CompareKind::Ge;
  case ir::CompareKind::Gt:
    return ir::CompareKind::Lt;
  case ir::CompareKind::Ge:
    return ir::CompareKind::Le;
  default:
    return c;
  }
}

/// The slots in an order where each comes after those it reads (except
/// the reads in `current`), in `order`; or, where there is none, a cycle
/// (its first slot repeated at its end).
std::vector<size_t>
topologicalOrder(const std::vector<std::vector<size_t>> &reads,
                 const std::vector<std::set<size_t>> &current,
                 std::vector<size_t> &order) {
  const size_t K = reads.size();
  std::vector<int> state(K, 0); // 0 new, 1 on the stack, 2 done
  std::vector<size_t> stack, cycle;
  order.clear();
  std::function<bool(size_t)> visit = [&](size_t k) {
    if (state[k] == 2)
      return true;
    if (state[k] == 1) {
      cycle.assign(std::find(stack.begin(), stack.end(), k), stack.end());
      cycle.push_back(k);
      return false;
    }
    state[k] = 1;
    stack.push_back(k);
    for (size_t j : reads[k])
      if (!current[k].count(j) && !visit(j))
        return false;
    stack.pop_back();
    state[k] = 2;
    order.push_back(k);
    return true;
  };
  for (size_t k = 0; k < K; ++k)
    if (!visit(k))
      return cycle;
  return {};
}

class EventBuilder {
public:
  EventBuilder(PassContext &pc, EventResult &out)
      : pc_(pc), m_(pc.model), ctx_(m_.ctx()), out_(out) {}
  bool run();

private:
  void initialDiscreteValues();
  /// What initialPreValue made of an initial equation.
  enum class PreEquation { Used, Several, NotOne };
  PreEquation initialPreValue(const ir::Equation &e);
  bool activeAtInitialization(const ir::WhenClause &w) const;
  bool solveInitialPreValues();
  bool startFromInitialEquation(ir::VarId v, ir::ExprRef value, bool fixed);
  /// The parameters `e` reads were folded into a value of the compiled
  /// model: they fix it (ir::Parameter::structural).
  void markStructural(ir::ExprRef e);
  void stepFunctionEvents();
  void whenAsserts();
  void derivativesOutsideEquations();
  bool partitionEquations();
  void collectSlots();
  void addParameters();
  bool resolveDelays(ir::Substitution &frozen);
  ir::ExprRef atEventsOnly(ir::ExprRef e, ir::Substitution &frozen,
                           std::set<ir::VarId> &visiting,
                           std::string &varying);
  bool defineVariables(std::vector<ir::ExprRef> &def);
  ir::ExprRef risen(size_t clause);
  ir::ExprRef fired(size_t clause);
  bool buildUpdate();
  bool checkWhenLoops();
  bool buildTimeEvents();
  void chooseMode();
  ir::ExprRef cur(size_t k) { return ctx_.param(out_.current(k)); }
  ir::ExprRef pre(size_t k) { return ctx_.param(out_.pre(k)); }
  /// pre(v) as the update reads it: for a discrete variable with
  /// fixed = true, its start value while initial() holds (MLS 8.6: pre(v)
  /// = v.start is an equation of the initialization, which the rounds of
  /// the initial event must not move), so what reads it (MSL's Digital
  /// gates, `y = pre(aux)`) changes after the initialization, in the event
  /// iteration at the start time, where `change(x)` then fires.
  ir::ExprRef preDuringInitialization(size_t k) {
    const Slot &s = slots_[k];
    if (initialSlot_ < 0 || s.kind != ir::DiscreteKind::Variable)
      return pre(k);
    const ir::Variable &v = m_.variables[s.var];
    if (!v.fixed)
      return pre(k);
    return ctx_.ifThenElse(
        cur(static_cast<size_t>(initialSlot_)),
        v.startBinding ? v.startBinding : ctx_.constant(v.start), pre(k));
  }
  double startValue(ir::ExprRef e);

  PassContext &pc_;
  ir::Model &m_;
  ir::ExprContext &ctx_;
  EventResult &out_;
  std::vector<bool> discrete_;
  std::vector<ir::Equation> continuous_, discreteEqs_;
  std::vector<Slot> slots_;
  std::map<ir::VarId, size_t> slotOfVar_;
  std::map<ir::ExprRef, size_t, ir::ExprIdLess> slotOfRelation_;
  /// The slots of each clause's condition elements (one for a scalar).
  std::vector<std::vector<size_t>> slotsOfWhen_;
  int initialSlot_ = -1;
  /// The definition of each slot's new value (see the file comment), and
  /// the substitution that makes definitions: discrete variables read
  /// their new values, pre() of a continuous variable its value just
  /// before the event (y), time relations their right limit.
  std::vector<ir::ExprRef> def_;
  std::map<size_t, std::string> definedBy_; // slot -> its equation's text
  std::unique_ptr<ir::Substitution> defSubst_;
  /// Unknowns with the equation der(v) = 0 (parameters with fixed = false).
  std::set<ir::VarId> constantInTime_;
  /// Initial equations of the discrete initialization.
  std::vector<ir::Equation> discreteInitial_;
  /// Per slot, its pre() value during the initialization where initial
  /// equations give it (DiscreteInitialization.h), or null.
  std::vector<ir::ExprRef> initialPre_;
};

/// Sets v's start to `value` (of parameters, evaluated now) given by the
/// initial equation e; false when it cannot be evaluated.
bool EventBuilder::startFromInitialEquation(ir::VarId v, ir::ExprRef value,
                                            bool fixed) {
  ir::EvalEnv env = pc_.startEnv();
  env.time = m_.experiment.startTime.value_or(0.0);
  Expected<double> x = ir::evaluate(value, env, &m_);
  if (!x)
    return false;
  // Folded into the discrete start: a run cannot evaluate it again.
  markStructural(value);
  m_.variables[v].start = *x;
  m_.variables[v].hasStart = true;
  m_.variables[v].fixed = m_.variables[v].fixed || fixed;
  return true;
}

/// `initial equation heat = false;`: an initial equation of discrete
/// values that gives a variable which only when-clauses inactive at
/// initialization assign (so that it keeps pre(v) there) sets its start
/// value (the initial event starts from it); it is no equation of the
/// continuous initialization. The other initial equations of discrete
/// values (a variable a discrete equation or a when-clause active at
/// initialization defines, several pre() values) go to the discrete
/// initialization (DiscreteInitialization.h).
void EventBuilder::initialDiscreteValues() {
  std::vector<bool> heldAtInitialization(m_.variables.size(), false);
  for (const ir::WhenClause &w : m_.whenClauses)
    for (ir::ExprRef t : w.targets)
      heldAtInitialization[t->var()] = true;
  for (const ir::WhenClause &w : m_.whenClauses)
    if (activeAtInitialization(w))
      for (ir::ExprRef t : w.targets)
        heldAtInitialization[t->var()] = false;
  std::vector<ir::Equation> kept;
  for (ir::Equation &e : m_.initialEquations) {
    const bool ofVariables = ir::isDiscreteEquation(e.residual, discrete_);
    bool used = false, defined = false;
    for (ir::VarKey k : ir::freeVariables(e.residual)) {
      if (!ofVariables || used || k.order != 0 ||
          m_.variables[k.var].input != ir::EventInput::None ||
          !discrete_[k.var])
        continue;
      if (!heldAtInitialization[k.var]) {
        defined = true;
        continue;
      }
      ir::ExprRef value = ir::solveLinear(ctx_, e.residual, k.var);
      used = value && startFromInitialEquation(k.var, value, /*fixed=*/false);
    }
    if (used)
      continue;
    switch (defined ? PreEquation::Several : initialPreValue(e)) {
    case PreEquation::Used:
      break;
    case PreEquation::Several:
      discreteInitial_.push_back(std::move(e));
      break;
    case PreEquation::NotOne:
      kept.push_back(std::move(e));
      break;
    }
  }
  m_.initialEquations = std::move(kept);
}

/// `initial equation pre(y) = pre_y_start;` (MSL's OnOffController and
/// MathInteger blocks): pre(y) is an unknown of the initialization
/// (MLS 8.6) that the equation gives from parameters. It becomes the
/// discrete variable's start, fixed, so that the rounds of the initial
/// event hold it as they hold pre(v) = v.start (preDuringInitialization);
/// y itself is then computed by its own equation. An equation of several
/// pre() values (StateGraph's `pre(newActive) = pre(localActive)`) is one
/// of the discrete initialization.
EventBuilder::PreEquation EventBuilder::initialPreValue(const ir::Equation &e) {
  if (ir::readsContinuous(e.residual, discrete_))
    return PreEquation::NotOne;
  for (ir::VarKey k : ir::freeVariables(e.residual))
    if (k.order == 0)
      return PreEquation::Several; // a variable and pre() values
  std::vector<ir::VarId> pres;
  ir::ExprRef roots[] = {e.residual};
  ir::postOrder(roots, [&](ir::ExprRef n) {
    if (n->kind() == ir::ExprKind::Pre && n->var() < discrete_.size() &&
        discrete_[n->var()] &&
        std::find(pres.begin(), pres.end(), n->var()) == pres.end())
      pres.push_back(n->var());
  });
  if (pres.size() > 1)
    return PreEquation::Several;
  if (pres.size() != 1 ||
      m_.variables[pres[0]].input != ir::EventInput::None)
    return PreEquation::NotOne;
  // pre(v) as the unknown: solved as a variable would be.
  const ir::VarId v = pres[0];
  ir::Substitution asVariable(ctx_);
  asVariable.set(ctx_.pre(v), ctx_.var(v));
  ir::ExprRef value = ir::solveLinear(ctx_, asVariable.apply(e.residual), v);
  if (value && startFromInitialEquation(v, value, /*fixed=*/true))
    return PreEquation::Used;
  return PreEquation::Several;
}

/// An assert in a when-clause (MSL's hard stops check their start in
/// `when initial() then assert(...)`) is checked where the clause fires:
/// the clause assigns its condition to a discrete Boolean, and each value
/// its message shows to a discrete Real, and an ordinary assert of the
/// Boolean, checked at the rows after the event, reports them.
void EventBuilder::whenAsserts() {
  size_t count = 0;
  auto generated = [&](const std::string &name, bool isBoolean, double start,
                       SourceLoc loc) {
    ir::Variable v;
    v.name = name + " #" + std::to_string(++count);
    v.loc = loc;
    v.isDiscrete = v.generated = true;
    v.isBoolean = isBoolean;
    v.start = start;
    v.hasStart = v.fixed = true;
    return ctx_.var(m_.addVariable(std::move(v)));
  };
  for (ir::WhenClause &w : m_.whenClauses) {
    auto assign = [&](ir::ExprRef target, ir::ExprRef value, SourceLoc loc) {
      ir::Equation e;
      e.residual = ctx_.sub(target, value);
      e.loc = loc;
      e.text = m_.variables[target->var()].name + " = " +
               ir::printLsd(value, &m_);
      w.equations.push_back(std::move(e));
      w.targets.push_back(target);
    };
    for (ir::Assert &a : w.asserts) {
      std::string what = "assert(" + ir::printLsd(a.condition, &m_) + ")";
      ir::ExprRef holds = generated(what, true, 1, a.loc);
      assign(holds, a.condition, a.loc);
      for (ir::ExprRef &v : a.messageValues) {
        ir::ExprRef kept = generated(ir::printLsd(v, &m_), false, 0, a.loc);
        assign(kept, v, a.loc);
        v = kept;
      }
      a.condition = holds;
      m_.asserts.push_back(std::move(a));
    }
    w.asserts.clear();
  }
}

/// der(y) read only where no equation reads it (OpenModelica's
/// derInWhenCondition: `when der(y) < 0 then`, y algebraic) is an unknown
/// of its own, d = der(y) an equation of the system, so that the
/// structural analysis differentiates y's equations for it; it reached
/// code generation as no unknown of the system.
void EventBuilder::derivativesOutsideEquations() {
  std::set<ir::VarKey> inEquations;
  for (const ir::Equation &e : m_.equations)
    for (ir::VarKey k : ir::freeVariables(e.residual))
      inEquations.insert(k);
  std::vector<ir::ExprRef *> places;
  for (ir::WhenClause &w : m_.whenClauses) {
    places.push_back(&w.condition);
    for (ir::ExprRef &c : w.elements)
      places.push_back(&c);
    for (ir::Equation &e : w.equations)
      places.push_back(&e.residual);
    for (ir::Reinit &r : w.reinits)
      places.push_back(&r.value);
  }
  for (ir::Assert &a : m_.asserts) {
    places.push_back(&a.condition);
    for (ir::ExprRef &v : a.messageValues)
      places.push_back(&v);
  }
  ir::Substitution derivative(ctx_);
  bool any = false;
  for (ir::ExprRef *place : places)
    for (ir::VarKey k : ir::freeVariables(*place)) {
      if (k.order == 0 || inEquations.count(k))
        continue;
      inEquations.insert(k);
      ir::ExprRef der = ctx_.var(k.var, k.order);
      ir::Variable v;
      v.name = ir::printLsd(der, &m_);
      v.loc = m_.variables[k.var].loc;
      v.generated = true;
      ir::ExprRef d = ctx_.var(m_.addVariable(std::move(v)));
      ir::Equation e;
      e.residual = ctx_.sub(d, der);
      e.loc = m_.variables[k.var].loc;
      e.text = m_.variables[d->var()].name + " = " + ir::printLsd(der, &m_);
      m_.equations.push_back(std::move(e));
      derivative.set(der, d);
      any = true;
    }
  if (!any)
    return;
  for (ir::ExprRef *place : places)
    *place = derivative.apply(*place);
}

/// floor(x) and ceil(x) (integer(x) is floor) of a continuous or
/// time-dependent x jump where x crosses an integer. Each becomes a
/// discrete Integer k, assigned at the crossings by
///   when {initial(), x >= k + 1, x < k} then k = floor(x);
///   (ceil: x > k, x <= k - 1)
/// whose relations the integrator locates, as OpenModelica makes events of
/// them (its mathFunctionEvents test): MSL's StateGraphRoot counts its
/// active steps as integer() of a flow sum.
void EventBuilder::stepFunctionEvents() {
  // Initial equations (and initial algorithms) are evaluated once, at the
  // start: their step functions need no events and keep their argument.
  // So is a when-clause's body, at the events that fire it (MLS 8.5: no
  // crossing functions there): MSL's impureRandomInteger takes integer()
  // of a random number its when-clause draws.
  std::vector<ir::ExprRef> roots;
  for (const ir::Equation &e : m_.equations)
    roots.push_back(e.residual);
  for (const ir::WhenClause &w : m_.whenClauses)
    for (ir::ExprRef c : conditionsOf(w))
      roots.push_back(c);
  ir::Substitution stepOf(ctx_);
  std::vector<ir::WhenClause> clauses;
  ir::ExprRef initial = nullptr;
  for (ir::ExprRef n : ir::topologicalOrder(roots)) {
    if (n->kind() != ir::ExprKind::Call ||
        (n->func() != ir::FuncKind::Floor && n->func() != ir::FuncKind::Ceil))
      continue;
    ir::ExprRef x = n->operand(0);
    if (!ir::dependsOnTime(x) && !ir::readsContinuous(x, discrete_))
      continue;
    if (!initial) {
      std::optional<ir::VarId> iv = m_.findVariable("initial()");
      if (!iv) {
        ir::Variable v;
        v.name = "initial()";
        v.isDiscrete = v.isBoolean = true;
        v.input = ir::EventInput::Initial;
        iv = m_.addVariable(std::move(v));
        discrete_.push_back(true);
      }
      initial = ctx_.var(*iv);
    }
    ir::Variable v;
    v.name = ir::printLsd(n, &m_);
    v.isDiscrete = v.isInteger = v.generated = true;
    ir::VarId k = m_.addVariable(std::move(v));
    discrete_.push_back(true);
    ir::ExprRef kv = ctx_.var(k);
    bool up = n->func() == ir::FuncKind::Floor;
    ir::ExprRef one = ctx_.one();
    ir::WhenClause w;
    w.elements = {
        initial,
        up ? ctx_.compare(ir::CompareKind::Ge, x, ctx_.add(kv, one))
           : ctx_.compare(ir::CompareKind::Gt, x, kv),
        up ? ctx_.compare(ir::CompareKind::Lt, x, kv)
           : ctx_.compare(ir::CompareKind::Le, x, ctx_.sub(kv, one))};
    w.condition = ctx_.logicalOr(w.elements);
    w.loc = m_.loc;
    ir::Equation assign;
    assign.residual = ctx_.sub(kv, n);
    assign.loc = m_.loc;
    assign.text = m_.variables[k].name + " = " + m_.variables[k].name;
    w.equations.push_back(std::move(assign));
    w.targets.push_back(kv);
    clauses.push_back(std::move(w));
    stepOf.set(n, kv);
  }
  if (clauses.empty())
    return;
  for (ir::Equation &e : m_.equations)
    e.residual = stepOf.apply(e.residual);
  for (ir::WhenClause &w : m_.whenClauses) {
    for (ir::Equation &e : w.equations)
      e.residual = stepOf.apply(e.residual);
    for (ir::Reinit &r : w.reinits)
      r.value = stepOf.apply(r.value);
    w.condition = stepOf.apply(w.condition);
    for (ir::ExprRef &c : w.elements)
      c = stepOf.apply(c);
  }
  for (ir::Assert &a : m_.asserts) {
    a.condition = stepOf.apply(a.condition);
    for (ir::ExprRef &v : a.messageValues)
      v = stepOf.apply(v);
  }
  for (ir::WhenClause &w : clauses)
    m_.whenClauses.push_back(std::move(w));
}

bool EventBuilder::partitionEquations() {
  for (ir::Equation &e : m_.equations)
    (ir::isDiscreteEquation(e.residual, discrete_) ? discreteEqs_
                                                   : continuous_)
        .push_back(e);
  // `Integer i = integer(10 * sin(10 * time))`: a discrete value that a
  // step function of a continuous argument defines changes where that
  // argument crosses an integer, events the relations do not locate; it
  // would keep its value until some other event (OpenModelica's
  // mathFunctionEvents). Refused, never a stale value.
  bool ok = true;
  for (const ir::Equation &e : discreteEqs_)
    for (ir::ExprRef n : ir::topologicalOrder(std::span(&e.residual, 1))) {
      if (n->kind() != ir::ExprKind::Call ||
          (n->func() != ir::FuncKind::Floor && n->func() != ir::FuncKind::Ceil &&
           n->func() != ir::FuncKind::Mod))
        continue;
      bool continuousArgument = false;
      for (ir::ExprRef a : n->operands())
        continuousArgument = continuousArgument || ir::dependsOnTime(a) ||
                             ir::readsContinuous(a, discrete_);
      if (!continuousArgument)
        continue;
      pc_.diags.report(DiagId::ErrDiscreteStepFunction, e.loc,
                       {e.text, ir::funcName(n->func())});
      ok = false;
      break;
    }
  return ok;
}

void EventBuilder::collectSlots() {
  // Discrete variables first, by VarId, then the relations in the order
  // the equations and conditions read them, then one per when-branch.
  for (ir::VarId v = 0; v < m_.variables.size(); ++v) {
    if (!discrete_[v])
      continue;
    const ir::Variable &var = m_.variables[v];
    Slot s;
    s.kind = inputKind(var.input);
    s.name = var.name;
    s.node = ctx_.var(v);
    s.var = v;
    slotOfVar_[v] = slots_.size();
    if (s.kind == ir::DiscreteKind::Initial)
      initialSlot_ = static_cast<int>(slots_.size());
    slots_.push_back(s);
  }
  std::vector<ir::ExprRef> roots;
  for (const ir::Equation &e : continuous_)
    roots.push_back(e.residual);
  for (const ir::Equation &e : discreteEqs_)
    roots.push_back(e.residual);
  for (const ir::Equation &e : m_.initialEquations)
    roots.push_back(e.residual);
  for (const ir::WhenClause &w : m_.whenClauses)
    for (ir::ExprRef c : conditionsOf(w))
      roots.push_back(c);
  for (ir::ExprRef n : ir::topologicalOrder(roots)) {
    if (!ir::isEventRelation(n, discrete_) || slotOfRelation_.count(n))
      continue;
    Slot s;
    s.kind = ir::DiscreteKind::Relation;
    s.name = ir::printLsd(n, &m_);
    s.node = n;
    // `time <op> e` with e over parameters and discrete values: a time
    // event, hit exactly.
    ir::ExprRef a = n->operand(0), b = n->operand(1);
    ir::CompareKind c = n->compare();
    if (b->kind() == ir::ExprKind::Time) {
      std::swap(a, b);
      c = mirrored(c);
    }
    if (a->kind() == ir::ExprKind::Time && !ir::dependsOnTime(b) &&
        c != ir::CompareKind::Eq && c != ir::CompareKind::Ne &&
        !ir::readsContinuous(b, discrete_)) {
      bool onlyDiscrete = true;
      for (ir::VarKey k : ir::freeVariables(b))
        onlyDiscrete = onlyDiscrete && k.order == 0;
      if (onlyDiscrete) {
        s.timeRelation = true;
        s.threshold = b;
        s.timeCompare = c;
      }
    }
    slotOfRelation_[n] = slots_.size();
    slots_.push_back(s);
  }
  for (size_t i = 0; i < m_.whenClauses.size(); ++i) {
    slotsOfWhen_.emplace_back();
    for (ir::ExprRef c : conditionsOf(m_.whenClauses[i])) {
      Slot s;
      s.kind = ir::DiscreteKind::When;
      s.name = "when " + ir::printLsd(c, &m_);
      s.when = static_cast<int>(i);
      s.condition = c;
      slotsOfWhen_.back().push_back(slots_.size());
      slots_.push_back(s);
    }
  }
}

/// delay(e, d) is set by the runtime from the values e took after each
/// event, which is e's whole history only when e changes at events alone:
/// it reads discrete values, pre() and relations, or variables that the
/// continuous equations give from those (MSL's TransportDelay delays `xr`
/// of `xr = Integer(pre(x))`). A delay of what varies between events
/// would need the runtime to keep and interpolate a continuous history:
/// refused at the call.
bool EventBuilder::resolveDelays(ir::Substitution &frozen) {
  bool ok = true;
  for (Slot &s : slots_) {
    if (s.kind != ir::DiscreteKind::Delay)
      continue;
    const ir::Variable &v = m_.variables[s.var];
    std::set<ir::VarId> visiting;
    std::string varying;
    s.delayed = atEventsOnly(frozen.apply(v.delayed), frozen, visiting,
                             varying);
    if (s.delayed)
      continue;
    pc_.diags.report(DiagId::ErrDelayContinuous, v.loc, {v.name, varying});
    ok = false;
  }
  return ok;
}

/// `e` (in the frozen form) with each continuous variable replaced by the
/// value an equation gives it from values that change at events only;
/// null, with the first variable (or `time`) that varies between events in
/// `varying`, when there is none.
ir::ExprRef EventBuilder::atEventsOnly(ir::ExprRef e, ir::Substitution &frozen,
                                       std::set<ir::VarId> &visiting,
                                       std::string &varying) {
  if (ir::dependsOnTime(e)) {
    varying = "time";
    return nullptr;
  }
  // pre() of a continuous variable (those of discrete ones are Parameters
  // in the frozen form) follows it between events.
  for (ir::ExprRef n : ir::topologicalOrder(std::span(&e, 1)))
    if (n->kind() == ir::ExprKind::Pre) {
      varying = "pre(" + m_.variables[n->var()].name + ")";
      return nullptr;
    }
  ir::Substitution given(ctx_);
  for (ir::VarKey k : ir::freeVariables(e)) {
    if (k.order != 0 || !visiting.insert(k.var).second) {
      varying = m_.variableName(k);
      return nullptr;
    }
    ir::ExprRef value = nullptr;
    for (const ir::Equation &eq : continuous_) {
      if (!ir::dependsOn(eq.residual, k))
        continue;
      ir::ExprRef f = ir::solveLinear(ctx_, frozen.apply(eq.residual), k.var);
      std::string inner;
      if (f && (value = atEventsOnly(f, frozen, visiting, inner)))
        break;
    }
    visiting.erase(k.var);
    if (!value) {
      varying = m_.variableName(k);
      return nullptr;
    }
    given.set(ctx_.var(k.var), value);
  }
  return given.apply(e);
}

void EventBuilder::markStructural(ir::ExprRef e) {
  for (ir::ParamId p : ir::freeParameters(e))
    if (p < m_.parameters.size())
      m_.parameters[p].structural = true;
}

double EventBuilder::startValue(ir::ExprRef e) {
  ir::EvalEnv env = pc_.startEnv();
  env.time = m_.experiment.startTime.value_or(0.0);
  Expected<double> v = ir::evaluate(e, env, &m_);
  return v ? *v : 0.0;
}

void EventBuilder::addParameters() {
  out_.base = static_cast<ir::ParamId>(m_.parameters.size());
  for (const Slot &s : slots_) {
    ir::DiscreteValue d;
    d.name = s.name;
    d.kind = s.kind;
    if (s.kind == ir::DiscreteKind::Variable) {
      d.start = m_.variables[s.var].start;
      // Discrete start values are no run-time parameters' bindings
      // (ldae_model::bind covers the unknowns'): what they read is fixed.
      if (ir::ExprRef b = m_.variables[s.var].startBinding)
        markStructural(b);
    }
    else if (s.kind == ir::DiscreteKind::Relation)
      d.start = startValue(s.node);
    else if (s.kind == ir::DiscreteKind::When)
      d.start = startValue(s.condition) != 0 ? 1 : 0;
    out_.discrete.push_back(d);
  }
  // Names print verbatim: the variable, `(h <= 0)` for a relation's
  // frozen value, `pre(heat)`.
  auto add = [&](const std::string &name, double value) {
    ir::Parameter p;
    p.name = name;
    p.value = value;
    p.discrete = true;
    m_.addParameter(std::move(p));
  };
  for (size_t k = 0; k < slots_.size(); ++k) {
    const Slot &s = slots_[k];
    add(s.kind == ir::DiscreteKind::Relation || s.kind == ir::DiscreteKind::When
            ? "(" + s.name + ")"
            : s.name,
        out_.discrete[k].start);
  }
  for (size_t k = 0; k < slots_.size(); ++k)
    add("pre(" + slots_[k].name + ")", out_.discrete[k].start);
}

/// Which discrete equation defines which discrete variable (a matching:
/// the equation must be solvable for it, linearly), and the value.
bool EventBuilder::defineVariables(std::vector<ir::ExprRef> &value) {
  std::vector<bool> whenAssigned(m_.variables.size(), false);
  for (const ir::WhenClause &w : m_.whenClauses)
    for (ir::ExprRef t : w.targets)
      whenAssigned[t->var()] = true;
  // Where a when-clause assigns a variable, for messages.
  std::map<ir::VarId, std::string> assignedIn;
  for (const ir::WhenClause &w : m_.whenClauses)
    for (ir::ExprRef t : w.targets)
      assignedIn.emplace(t->var(), "when " + ir::printLsd(w.condition, &m_));
  std::set<ir::VarId> reported;
  std::vector<ir::VarId> vars;
  std::map<ir::VarId, int> column;
  for (const Slot &s : slots_)
    if (s.kind == ir::DiscreteKind::Variable && !whenAssigned[s.var]) {
      column[s.var] = static_cast<int>(vars.size());
      vars.push_back(s.var);
    }
  // The solved form of equation e for each variable it is linear in.
  std::vector<std::map<int, ir::ExprRef>> solved(discreteEqs_.size());
  graph::BipartiteGraph g(static_cast<int>(discreteEqs_.size()),
                          static_cast<int>(vars.size()));
  for (size_t e = 0; e < discreteEqs_.size(); ++e) {
    ir::ExprRef r = discreteEqs_[e].residual;
    for (ir::VarKey k : ir::freeVariables(r)) {
      auto it = column.find(k.var);
      if (k.order != 0 || it == column.end())
        continue;
      ir::ExprRef value = ir::solveLinear(ctx_, r, k.var);
      if (!value)
        continue;
      solved[e][it->second] = value;
      g.rows[e].push_back(it->second);
    }
  }
  graph::Matching mt = graph::maximumMatching(g);
  bool ok = true;
  for (size_t e = 0; e < discreteEqs_.size(); ++e) {
    if (mt.rowMate[e] >= 0)
      continue;
    ok = false;
    const ir::Equation &eq = discreteEqs_[e];
    if (!g.rows[e].empty()) {
      // Every variable it could define is defined by another equation.
      int j = g.rows[e][0];
      pc_.diags.report(DiagId::ErrDiscreteTwice, eq.loc,
                       {m_.variables[vars[j]].name, eq.text,
                        discreteEqs_[mt.colMate[j]].text});
      continue;
    }
    std::optional<ir::VarId> var;
    for (ir::VarKey k : ir::freeVariables(eq.residual))
      if (discrete_[k.var] && !var &&
          m_.variables[k.var].input == ir::EventInput::None)
        var = k.var;
    std::string name = var ? m_.variables[*var].name : "";
    if (var)
      reported.insert(*var);
    if (var && whenAssigned[*var])
      pc_.diags.report(DiagId::ErrDiscreteTwice, eq.loc,
                       {name, eq.text, assignedIn[*var]});
    else
      pc_.diags.report(DiagId::ErrDiscreteNotSolvable, eq.loc,
                       {eq.text, name});
  }
  for (size_t j = 0; j < vars.size(); ++j) {
    int e = mt.colMate[j];
    if (e < 0) {
      ok = false;
      if (!reported.count(vars[j]))
        pc_.diags.report(DiagId::ErrDiscreteUndefined,
                       m_.variables[vars[j]].loc, {m_.variables[vars[j]].name});
      continue;
    }
    value[slotOfVar_[vars[j]]] = solved[e][static_cast<int>(j)];
    definedBy_[slotOfVar_[vars[j]]] = discreteEqs_[e].text;
  }
  return ok;
}

/// Whether the condition of branch `clause` rose at this event: one of
/// its elements is 1 and its pre() is 0; during the initial event only an
/// element with initial() fires (and does, whatever its pre()).
ir::ExprRef EventBuilder::risen(size_t clause) {
  const Slot &initial = slots_[static_cast<size_t>(initialSlot_)];
  ir::ExprRef init = cur(static_cast<size_t>(initialSlot_));
  std::vector<ir::ExprRef> any;
  // initial() rises once, in the first update of the initial event (its
  // pre() is 0 there only): a when initial() fires once, not in every
  // round of the event iteration (OpenModelica's pre3 never settled).
  ir::ExprRef initRose = ctx_.logicalAnd(
      init, ctx_.logicalNot(pre(static_cast<size_t>(initialSlot_))));
  for (size_t k : slotsOfWhen_[clause]) {
    if (slots_[k].condition == initial.node)
      any.push_back(ctx_.logicalAnd(
          cur(k), ctx_.logicalOr(initRose,
                                 ctx_.logicalAnd(ctx_.logicalNot(init),
                                                 ctx_.logicalNot(pre(k))))));
    else
      any.push_back(ctx_.logicalAnd(std::vector<ir::ExprRef>{
          cur(k), ctx_.logicalNot(pre(k)), ctx_.logicalNot(init)}));
  }
  return ctx_.logicalOr(any);
}

/// MLS 8.6: a when-clause is active at the initialization only where its
/// condition is `initial()` or a vector with `initial()` as an element;
/// `when initial() or time > 0.5` is not (OpenModelica warns of it, and
/// its discreteTest6 expects y = 0 at the start).
bool EventBuilder::activeAtInitialization(const ir::WhenClause &w) const {
  for (ir::ExprRef c : conditionsOf(w))
    if (c->kind() == ir::ExprKind::Variable &&
        m_.variables[c->var()].input == ir::EventInput::Initial)
      return true;
  return false;
}

/// Whether branch `clause` fires: it rose and no earlier branch of the
/// same when-equation did (elsewhen priority).
ir::ExprRef EventBuilder::fired(size_t clause) {
  ir::ExprRef f = risen(clause);
  for (size_t j = clause; j > 0 && m_.whenClauses[j].elsewhen; --j)
    f = ctx_.logicalAnd(f, ctx_.logicalNot(risen(j - 1)));
  return f;
}

/// A when-equation `v = e` is evaluated from the continuous point before
/// the event and the continuous values are then solved with the new v; an
/// e that reads an algebraic value which the continuous equations
/// determine from v itself (OpenModelica's bug1228: `when ... then y = 7 -
/// 2*x + time`, `x + y = 5`) would need both solved together, which the
/// event iteration does not: refused at the when-equation, never a wrong
/// value. States are known at an event; the dependence follows a matching
/// of the continuous equations to the other unknowns.
bool EventBuilder::checkWhenLoops() {
  // The unknowns an event solves: every continuous key but the states
  // (variables whose derivative the equations read).
  std::vector<bool> state(m_.variables.size(), false);
  for (const ir::Equation &e : continuous_)
    for (ir::VarKey k : ir::freeVariables(e.residual))
      if (k.order > 0)
        state[k.var] = true;
  std::map<ir::VarKey, int> column;
  std::vector<ir::VarKey> keys;
  std::vector<std::vector<ir::VarKey>> reads(continuous_.size());
  for (size_t e = 0; e < continuous_.size(); ++e)
    for (ir::VarKey k : ir::freeVariables(continuous_[e].residual)) {
      reads[e].push_back(k);
      if (discrete_[k.var] || (k.order == 0 && state[k.var]) ||
          column.count(k))
        continue;
      column[k] = static_cast<int>(keys.size());
      keys.push_back(k);
    }
  graph::BipartiteGraph g(static_cast<int>(continuous_.size()),
                          static_cast<int>(keys.size()));
  for (size_t e = 0; e < continuous_.size(); ++e)
    for (ir::VarKey k : reads[e])
      if (auto it = column.find(k); it != column.end())
        g.rows[e].push_back(it->second);
  graph::Matching mt = graph::maximumMatching(g);
  // What each key determines: the unknown of every equation reading it.
  std::map<ir::VarKey, std::vector<ir::VarKey>> feeds;
  for (size_t e = 0; e < continuous_.size(); ++e) {
    if (mt.rowMate[e] < 0)
      continue;
    ir::VarKey solved = keys[static_cast<size_t>(mt.rowMate[e])];
    for (ir::VarKey k : reads[e])
      if (!(k == solved))
        feeds[k].push_back(solved);
  }
  for (const ir::WhenClause &w : m_.whenClauses)
    for (size_t a = 0; a < w.targets.size(); ++a) {
      ir::VarKey target{w.targets[a]->var(), 0};
      std::set<ir::VarKey> reached;
      std::vector<ir::VarKey> todo{target};
      while (!todo.empty()) {
        ir::VarKey k = todo.back();
        todo.pop_back();
        for (ir::VarKey u : feeds[k])
          if (reached.insert(u).second)
            todo.push_back(u);
      }
      for (ir::VarKey k : ir::freeVariables(w.equations[a].residual)) {
        if (!reached.count(k))
          continue;
        pc_.diags.report(DiagId::ErrWhenAlgebraicLoop, w.equations[a].loc,
                         {w.equations[a].text, m_.variableName(k),
                          m_.variables[target.var].name});
        return false;
      }
    }
  return true;
}

bool EventBuilder::buildUpdate() {
  const size_t K = slots_.size();
  defSubst_ = std::make_unique<ir::Substitution>(ctx_);
  ir::Substitution &sd = *defSubst_;
  for (size_t k = 0; k < K; ++k)
    if (slots_[k].node && slots_[k].kind != ir::DiscreteKind::Relation) {
      sd.set(slots_[k].node, cur(k));
      sd.set(ctx_.pre(slots_[k].var), preDuringInitialization(k));
    }
  // pre(x) of a continuous x: its value just before the event.
  std::vector<ir::ExprRef> all;
  for (const ir::WhenClause &w : m_.whenClauses) {
    for (const ir::Equation &e : w.equations)
      all.push_back(e.residual);
    for (const ir::Reinit &r : w.reinits)
      all.push_back(r.value);
    for (ir::ExprRef c : conditionsOf(w))
      all.push_back(c);
  }
  for (const ir::Equation &e : discreteEqs_)
    all.push_back(e.residual);
  for (ir::ExprRef n : ir::topologicalOrder(all))
    if (n->kind() == ir::ExprKind::Pre && !discrete_[n->var()])
      sd.set(n, ctx_.var(n->var()));
  // Time relations at their right limit: `time > t0` is 1 at t0.
  for (const Slot &s : slots_)
    if (s.timeRelation) {
      bool above = s.timeCompare == ir::CompareKind::Gt ||
                   s.timeCompare == ir::CompareKind::Ge;
      ir::ExprRef thr = sd.apply(s.threshold);
      sd.set(s.node, ctx_.compare(above ? ir::CompareKind::Ge
                                        : ir::CompareKind::Lt,
                                  ctx_.time(), thr));
    }

  def_.assign(K, nullptr);
  std::vector<ir::ExprRef> solved(K, nullptr);
  bool ok = defineVariables(solved);
  for (size_t k = 0; k < K; ++k) {
    const Slot &s = slots_[k];
    switch (s.kind) {
    case ir::DiscreteKind::Variable:
      if (solved[k])
        def_[k] = sd.apply(solved[k]);
      break;
    case ir::DiscreteKind::Relation:
      def_[k] = sd.apply(s.node);
      break;
    case ir::DiscreteKind::When:
      def_[k] = sd.apply(s.condition);
      break;
    case ir::DiscreteKind::Delay: {
      // MLS 3.7.4.1: e(time.start) until start + d, so e's own value
      // while initial() holds (the runtime keeps the value the
      // initialization ends with); with d = 0, e's value always. After
      // that, the value the runtime set from e's history.
      ir::Substitution held(ctx_);
      for (size_t j = 0; j < K; ++j)
        if (slots_[j].kind == ir::DiscreteKind::Variable)
          held.set(pre(j), preDuringInitialization(j));
      ir::ExprRef now = ctx_.logicalOr(
          cur(static_cast<size_t>(initialSlot_)),
          ctx_.compare(ir::CompareKind::Le, m_.variables[s.var].delayTime,
                       ctx_.zero()));
      def_[k] = ctx_.ifThenElse(now, held.apply(s.delayed), cur(k));
      break;
    }
    default: // inputs: the runtime sets them; the update copies them
      def_[k] = cur(k);
      break;
    }
  }
  // when-assignments: `if fired then e else pre(v)`, the first branch
  // (in source order) that fires deciding.
  for (size_t i = m_.whenClauses.size(); i-- > 0;) {
    const ir::WhenClause &w = m_.whenClauses[i];
    for (size_t a = 0; a < w.targets.size(); ++a) {
      size_t k = slotOfVar_[w.targets[a]->var()];
      ir::ExprRef value =
          sd.apply(ctx_.sub(w.targets[a], w.equations[a].residual));
      def_[k] = ctx_.ifThenElse(fired(i), value, def_[k] ? def_[k] : pre(k));
    }
  }
  // Inline in dependency order: D_k reads the new values of others as
  // their current Parameter.
  std::vector<std::vector<size_t>> reads(K);
  for (size_t k = 0; k < K; ++k) {
    if (!def_[k])
      def_[k] = pre(k);
    for (ir::ParamId p : ir::freeParameters(def_[k]))
      if (p >= out_.current(0) && p < out_.pre(0) && p != out_.current(k) &&
          !isInput(slots_[p - out_.base].kind))
        reads[k].push_back(p - out_.base);
  }
  // A cycle through a when-branch (`when time >= tnext then tnext =
  // pre(tnext) + 1`) is the event iteration's: the branch's condition reads
  // the current value of what follows it in the cycle, and the next
  // iteration sees the new one. A cycle of discrete equations alone has
  // no value: an error naming them.
  std::vector<std::set<size_t>> current(K); // reads of current values
  std::vector<size_t> order;
  for (;;) {
    std::vector<size_t> cycle = topologicalOrder(reads, current, order);
    if (cycle.empty())
      break;
    auto when = std::find_if(cycle.begin(), cycle.end() - 1, [&](size_t j) {
      return slots_[j].kind == ir::DiscreteKind::When;
    });
    if (when != cycle.end() - 1) {
      current[*when].insert(*(when + 1));
      continue;
    }
    std::string text;
    for (size_t j : cycle) {
      auto d = definedBy_.find(j);
      text += (text.empty() ? "'" : " -> '") +
              (d != definedBy_.end() ? d->second : slots_[j].name) + "'";
    }
    pc_.diags.report(DiagId::ErrDiscreteCycle, m_.loc, {text});
    return false;
  }
  if (!ok)
    return false;
  // A read of a current value is kept out of the inlining by a stand-in
  // (a ParamId no expression uses) put back afterwards.
  auto standIn = [&](size_t j) {
    return ctx_.param(out_.pre(0) + static_cast<ir::ParamId>(K + j));
  };
  ir::Substitution inl(ctx_), back(ctx_);
  for (size_t j = 0; j < K; ++j)
    back.set(standIn(j), cur(j));
  out_.update.assign(K, nullptr);
  for (size_t k : order) {
    ir::ExprRef d = def_[k];
    if (!current[k].empty()) {
      ir::Substitution hold(ctx_);
      for (size_t j : current[k])
        hold.set(cur(j), standIn(j));
      d = hold.apply(d);
    }
    out_.update[k] = back.apply(inl.apply(d));
    if (!isInput(slots_[k].kind))
      inl.set(cur(k), out_.update[k]);
  }

  for (size_t i = 0; i < m_.whenClauses.size(); ++i) {
    const ir::WhenClause &w = m_.whenClauses[i];
    ir::ExprRef f = inl.apply(fired(i));
    for (const ir::Reinit &r : w.reinits)
      out_.reinits.push_back(
          {r.var, inl.apply(sd.apply(r.value)), f, r.loc});
    for (const ir::Terminate &t : w.terminates)
      out_.terminates.push_back({f, t.message});
  }
  return true;
}

/// The pre() values initial equations give (DiscreteInitialization.h)
/// replace pre() in the first round of the initial event, where initial()
/// has just risen; the later rounds read the values before them, as the
/// event iteration does.
bool EventBuilder::solveInitialPreValues() {
  std::vector<DiscreteInitSlot> slots;
  for (const Slot &s : slots_)
    slots.push_back({s.kind, s.var,
                     s.kind == ir::DiscreteKind::Variable &&
                         m_.variables[s.var].fixed});
  if (!solveDiscreteInitialization(pc_, out_, slots, discreteInitial_,
                                   initialPre_))
    return false;
  if (initialSlot_ < 0)
    return true;
  const size_t init = static_cast<size_t>(initialSlot_);
  ir::ExprRef firstRound = ctx_.logicalAnd(cur(init), ctx_.logicalNot(pre(init)));
  ir::Substitution firstPre(ctx_);
  bool any = false;
  for (size_t k = 0; k < slots_.size(); ++k)
    if (initialPre_[k]) {
      firstPre.set(pre(k), ctx_.ifThenElse(firstRound, initialPre_[k], pre(k)));
      any = true;
    }
  if (!any)
    return true;
  for (ir::ExprRef &u : out_.update)
    u = firstPre.apply(u);
  for (EventResult::Reinit &r : out_.reinits) {
    r.value = firstPre.apply(r.value);
    r.fired = firstPre.apply(r.fired);
  }
  for (ir::TerminateUpdate &t : out_.terminates)
    t.fired = firstPre.apply(t.fired);
  return true;
}

bool EventBuilder::buildTimeEvents() {
  for (const ir::Equation &e : m_.equations)
    if (e.residual->kind() == ir::ExprKind::Variable &&
        e.residual->order() == 1)
      constantInTime_.insert(e.residual->var());
  // Roots, thresholds and asserts read the current (frozen) discrete
  // values; relations inside them are evaluated directly.
  ir::Substitution sr(ctx_);
  for (size_t k = 0; k < slots_.size(); ++k)
    if (slots_[k].node && slots_[k].kind != ir::DiscreteKind::Relation) {
      sr.set(slots_[k].node, cur(k));
      sr.set(ctx_.pre(slots_[k].var), pre(k));
    }
  bool ok = true;
  for (size_t k = 0; k < slots_.size(); ++k) {
    const Slot &s = slots_[k];
    if (s.kind == ir::DiscreteKind::Relation && s.timeRelation) {
      out_.timeThresholds.push_back(sr.apply(s.threshold));
      out_.thresholdRelation.push_back(static_cast<uint32_t>(k));
    } else if (s.kind == ir::DiscreteKind::Relation) {
      out_.roots.push_back(
          sr.apply(ctx_.sub(s.node->operand(0), s.node->operand(1))));
      out_.rootRelation.push_back(static_cast<uint32_t>(k));
    } else if (s.kind == ir::DiscreteKind::Sample) {
      const ir::Variable &v = m_.variables[s.var];
      ir::ExprRef parts[] = {v.sampleStart, v.sampleInterval};
      const char *what[] = {"start", "interval"};
      for (int i = 0; i < 2; ++i) {
        bool userParams = true;
        for (ir::ParamId p : ir::freeParameters(parts[i]))
          userParams = userParams && p < out_.base;
        // A parameter with fixed = false (MSL's Mean: `t0 = time` at the
        // initialization, `sample(t0 + 1/f, 1/f)`) is an unknown whose
        // der() is 0: constant once initialized, and the time events are
        // evaluated from the initialized point.
        bool constantUnknowns = true;
        for (ir::VarKey k : ir::freeVariables(parts[i]))
          constantUnknowns = constantUnknowns && k.order == 0 &&
                             constantInTime_.count(k.var) > 0;
        if (!constantUnknowns || ir::dependsOnTime(parts[i]) || !userParams) {
          pc_.diags.report(DiagId::ErrSampleNotParameter, v.loc, {what[i]});
          ok = false;
        }
      }
      out_.samples.push_back({parts[0], parts[1]});
      out_.sampleDiscrete.push_back(static_cast<uint32_t>(k));
    } else if (s.kind == ir::DiscreteKind::Delay) {
      // Without a maximum, d itself: the check d <= max holds.
      const ir::Variable &v = m_.variables[s.var];
      out_.delays.push_back({s.delayed, v.delayTime,
                             v.delayMax ? v.delayMax : v.delayTime,
                             static_cast<uint32_t>(k)});
    }
  }
  for (const ir::Assert &a : m_.asserts) {
    ir::AssertCheck check{sr.apply(a.condition), a.message, a.level, a.loc, {}};
    for (ir::ExprRef v : a.messageValues)
      check.messageValues.push_back(sr.apply(v));
    out_.asserts.push_back(std::move(check));
  }
  return ok;
}

/// Incidence of an expression: the continuous Variable nodes it reads.
std::vector<ir::VarKey> incidence(ir::ExprRef e) {
  return ir::freeVariables(e);
}

void EventBuilder::chooseMode() {
  // An if-equation (a residual `if c then r1 else r2`, elseif chains
  // nested in the else branch) whose branches read different unknowns: the
  // discrete values in c choose the structure. So does an if-expression
  // whose branches leave the residual reading different unknowns only
  // because a parameter in one of them is 0 (the MSL ideal diode's
  // `v = s * (if off then 1 else Ron)` with Ron = 0 drops s when
  // conducting): such a parameter is folded and fixes the structure. An
  // if-expression that reads different unknowns whatever the parameters
  // (a limiter's `if u > uMax then uMax else u`) keeps one structure, or
  // every limiter would double the modes.
  ir::Substitution zeros(ctx_);
  for (ir::ParamId p = 0; p < out_.base; ++p)
    if (m_.parameters[p].value == 0.0)
      zeros.set(ctx_.param(p), ctx_.constant(0.0));
  // `if initial() then ... else ... end if` (MSL's ElastoBacklash) chooses
  // the equations of the initialization, not a structure to switch to
  // after it: as a mode, the switch right after t = 0 moved the states by
  // the jump rule, where nothing jumps. It stays a piecewise residual.
  auto chosenBy = [&](ir::ExprRef r) {
    std::vector<uint32_t> slots;
    for (ir::ParamId p : ir::freeParameters(r->operand(0)))
      if (p >= out_.current(0) && p < out_.pre(0) &&
          int(p - out_.base) != initialSlot_)
        slots.push_back(p - out_.base);
    return slots;
  };
  std::set<uint32_t> mode;
  std::function<void(ir::ExprRef)> visitIfEquation = [&](ir::ExprRef r) {
    if (r->kind() != ir::ExprKind::If)
      return;
    if (incidence(r->operand(1)) != incidence(r->operand(2)))
      for (uint32_t k : chosenBy(r))
        mode.insert(k);
    visitIfEquation(r->operand(1));
    visitIfEquation(r->operand(2));
  };
  std::set<ir::ParamId> folded;
  auto visitIfExpression = [&](ir::ExprRef residual, ir::ExprRef r) {
    std::vector<ir::ParamId> zero;
    for (int b = 1; b <= 2; ++b)
      for (ir::ParamId p : ir::freeParameters(r->operand(b)))
        if (p < out_.base && m_.parameters[p].value == 0.0)
          zero.push_back(p);
    std::vector<uint32_t> slots = chosenBy(r);
    if (zero.empty() || slots.empty())
      return;
    auto pick = [&](ir::ExprRef branch, ir::Substitution *then) {
      ir::Substitution s(ctx_);
      s.set(r, branch);
      ir::ExprRef picked = s.apply(residual);
      return incidence(then ? then->apply(picked) : picked);
    };
    if (pick(r->operand(1), nullptr) != pick(r->operand(2), nullptr) ||
        pick(r->operand(1), &zeros) == pick(r->operand(2), &zeros))
      return;
    mode.insert(slots.begin(), slots.end());
    folded.insert(zero.begin(), zero.end());
  };
  for (const ir::Equation &e : m_.equations) {
    visitIfEquation(e.residual);
    for (ir::ExprRef r : ir::topologicalOrder(std::span(&e.residual, 1)))
      if (r->kind() == ir::ExprKind::If)
        visitIfExpression(e.residual, r);
  }
  if (!folded.empty()) {
    ir::Substitution fold(ctx_);
    for (ir::ParamId p : folded) {
      fold.set(ctx_.param(p), ctx_.constant(0.0));
      m_.parameters[p].structural = true;
    }
    for (ir::Equation &e : m_.equations)
      e.residual = fold.apply(e.residual);
    for (ir::Equation &e : m_.initialEquations)
      e.residual = fold.apply(e.residual);
  }
  if (mode.empty())
    return;
  out_.modeDiscrete.assign(mode.begin(), mode.end());
  const std::vector<double> &given = pc_.opts.modeValues;
  for (size_t i = 0; i < out_.modeDiscrete.size(); ++i)
    out_.modeValues.push_back(given.size() == mode.size()
                                  ? given[i]
                                  : out_.discrete[out_.modeDiscrete[i]].start);
  applyMode(m_, out_, out_.modeValues);
}

bool EventBuilder::run() {
  whenAsserts();
  derivativesOutsideEquations();
  discrete_ = ir::discreteVariables(m_);
  stepFunctionEvents();
  bool anyRelation = false;
  for (const ir::Equation &e : m_.equations)
    for (ir::ExprRef n : ir::topologicalOrder(std::span(&e.residual, 1)))
      anyRelation = anyRelation || ir::isEventRelation(n, discrete_);
  if (!anyRelation && m_.whenClauses.empty() && m_.asserts.empty() &&
      std::find(discrete_.begin(), discrete_.end(), true) == discrete_.end())
    return true;
  for (ir::VarId v = 0; v < m_.variables.size(); ++v)
    m_.variables[v].isDiscrete = discrete_[v];
  initialDiscreteValues();
  // when-clauses and the discrete initialization need initial() to know
  // the initial event, and so does delay() (e's own value at the start).
  bool anyDelay = false;
  for (const ir::Variable &v : m_.variables)
    anyDelay = anyDelay || v.input == ir::EventInput::Delay;
  if ((!m_.whenClauses.empty() || !discreteInitial_.empty() || anyDelay) &&
      !m_.findVariable("initial()")) {
    ir::Variable v;
    v.name = "initial()";
    v.isDiscrete = v.isBoolean = true;
    v.input = ir::EventInput::Initial;
    m_.addVariable(std::move(v));
    discrete_.push_back(true);
  }
  if (!partitionEquations())
    return false;
  collectSlots();
  addParameters();

  // The continuous equations read the frozen values.
  ir::Substitution sc(ctx_);
  for (size_t k = 0; k < slots_.size(); ++k) {
    const Slot &s = slots_[k];
    if (s.kind == ir::DiscreteKind::Relation) {
      sc.set(s.node, cur(k));
    } else if (s.node) {
      sc.set(s.node, cur(k));
      sc.set(ctx_.pre(s.var), pre(k));
    }
  }
  bool ok = resolveDelays(sc) && checkWhenLoops() && buildUpdate() &&
            solveInitialPreValues();
  ok = buildTimeEvents() && ok;
  for (ir::Equation &e : continuous_)
    e.residual = sc.apply(e.residual);
  // The initialization reads pre() values as the discrete initialization
  // gives them (x2 = pre(xd) in OpenModelica's pre3).
  ir::Substitution initialPre(ctx_);
  for (size_t k = 0; k < initialPre_.size(); ++k)
    if (initialPre_[k])
      initialPre.set(pre(k), initialPre_[k]);
  for (ir::Equation &e : m_.initialEquations)
    e.residual = initialPre.apply(sc.apply(e.residual));
  m_.equations = std::move(continuous_);
  if (!ok)
    return false;
  chooseMode();
  EventsReport rep;
  static const char *kinds[] = {"variable", "relation", "when",
                                "sample",   "initial",  "terminal",
                                "delay"};
  for (const ir::DiscreteValue &d : out_.discrete)
    rep.discrete.push_back(d.name + " (" + kinds[static_cast<int>(d.kind)] +
                           ")");
  for (ir::ExprRef r : out_.roots)
    rep.roots.push_back(ir::printLsd(r, &m_));
  for (ir::ExprRef t : out_.timeThresholds)
    rep.timeThresholds.push_back(ir::printLsd(t, &m_));
  rep.samples = static_cast<int>(out_.samples.size());
  rep.reinits = static_cast<int>(out_.reinits.size());
  rep.asserts = static_cast<int>(out_.asserts.size());
  for (uint32_t k : out_.modeDiscrete)
    rep.mode.push_back(out_.discrete[k].name);
  pc_.report.events = std::move(rep);
  return true;
}

class EventsPass
    : public TypedPass<EventsPass, Reads<>, Updates<>, Produces<EventResult>> {
public:
  EventsPass() : TypedPass(PassId::Events) {}
  bool runOn(PassContext &pc, EventResult &out) {
    pc.events = &out;
    return EventBuilder(pc, out).run();
  }
};

} // namespace

void applyMode(ir::Model &m, const EventResult &ev,
               std::span<const double> values) {
  ir::ExprContext &ctx = m.ctx();
  ir::Substitution s(ctx);
  for (size_t i = 0; i < ev.modeDiscrete.size() && i < values.size(); ++i)
    s.set(ctx.param(ev.current(ev.modeDiscrete[i])), ctx.constant(values[i]));
  for (ir::Equation &e : m.equations)
    e.residual = s.apply(e.residual);
  for (ir::Equation &e : m.initialEquations)
    e.residual = s.apply(e.residual);
}

void readUpdatedThroughSolved(ir::DaeSystem &sys,
                               const std::vector<ir::ExprRef> &before) {
  ir::ExprContext &ctx = *sys.ctx;
  std::vector<ir::ExprRef> &update = sys.events.update;
  const std::vector<ir::DiscreteValue> &discrete = sys.events.discrete;
  const size_t K = update.size();
  const ir::ParamId base = static_cast<ir::ParamId>(sys.parameterValues.size());
  auto currentReads = [&](ir::ExprRef e) {
    std::set<size_t> out;
    for (ir::ParamId p : ir::freeParameters(e))
      if (p >= base && p < base + K)
        out.insert(p - base);
    return out;
  };
  std::vector<std::vector<size_t>> reads(K);
  std::vector<std::set<size_t>> held(K);
  for (size_t k = 0; k < K && k < before.size(); ++k) {
    if (isInput(discrete[k].kind))
      continue;
    std::set<size_t> already = currentReads(before[k]);
    for (size_t j : currentReads(update[k]))
      if (j != k && !already.count(j) && !isInput(discrete[j].kind))
        reads[k].push_back(j);
  }
  // A cycle through solved unknowns keeps the event iteration's rounds.
  std::vector<size_t> order;
  for (;;) {
    std::vector<size_t> cycle = topologicalOrder(reads, held, order);
    if (cycle.empty())
      break;
    for (size_t i = 0; i + 1 < cycle.size(); ++i)
      held[cycle[i]].insert(cycle[i + 1]);
  }
  for (size_t k : order) {
    ir::Substitution s(ctx);
    bool any = false;
    for (size_t j : reads[k])
      if (!held[k].count(j)) {
        s.set(ctx.param(base + static_cast<ir::ParamId>(j)), update[j]);
        any = true;
      }
    if (any)
      update[k] = s.apply(update[k]);
  }
}

bool fillEvents(PassContext &pc, const EventResult &ev,
                const std::function<ir::ExprRef(ir::ExprRef)> &apply,
                ir::DaeSystem &sys) {
  const ir::Model &m = pc.model;
  ir::ExprContext &ctx = m.ctx();
  const size_t user = m.userParameterCount();
  sys.parameterValues.clear();
  sys.parameterNames.clear();
  for (size_t p = 0; p < user; ++p) {
    sys.parameterValues.push_back(m.parameters[p].value);
    sys.parameterNames.push_back(m.parameters[p].name);
  }
  if (ev.empty())
    return true;
  ir::EventSystem &es = sys.events;
  es.discrete = ev.discrete;
  for (ir::ExprRef e : ev.update)
    es.update.push_back(apply(e));
  readUpdatedThroughSolved(sys, ev.update);
  for (size_t j = 0; j < ev.roots.size(); ++j) {
    sys.roots.push_back(apply(ev.roots[j]));
    es.rootRelation.push_back(ev.rootRelation[j]);
  }
  for (ir::ExprRef e : ev.timeThresholds)
    es.timeThresholds.push_back(apply(e));
  es.thresholdRelation = ev.thresholdRelation;
  for (const auto &[start, interval] : ev.samples)
    es.samples.push_back({apply(start), apply(interval)});
  es.sampleDiscrete = ev.sampleDiscrete;
  for (const ir::DelayInput &d : ev.delays)
    es.delays.push_back(
        {apply(d.source), apply(d.time), apply(d.max), d.discrete});
  for (const ir::AssertCheck &a : ev.asserts) {
    ir::AssertCheck check{apply(a.condition), a.message, a.level, a.loc, {}};
    for (ir::ExprRef v : a.messageValues)
      check.messageValues.push_back(apply(v));
    es.asserts.push_back(std::move(check));
  }
  for (const ir::TerminateUpdate &t : ev.terminates)
    es.terminates.push_back({apply(t.fired), t.message});
  es.modeDiscrete = ev.modeDiscrete;
  es.modeValues = ev.modeValues;

  // A reinit writes a state's slot: through an alias `x = -y` it writes
  // y with the opposite sign.
  const std::vector<bool> differential = ir::anyDifferential(sys);
  bool ok = true;
  for (const EventResult::Reinit &r : ev.reinits) {
    ir::ExprRef target = apply(ctx.var(r.var));
    ir::ExprRef sign = ctx.one();
    if (target->kind() == ir::ExprKind::Mul && target->numOperands() == 2 &&
        target->operand(0)->isConstant()) {
      sign = target->operand(0);
      target = target->operand(1);
    }
    int slot = -1;
    if (target->kind() == ir::ExprKind::Variable)
      for (size_t i = 0; i < sys.unknowns.size(); ++i)
        if (sys.unknowns[i].key == target->varKey() && differential[i])
          slot = static_cast<int>(i);
    if (slot < 0) {
      pc.diags.report(DiagId::ErrReinitNotState, r.loc,
                      {m.variables[r.var].name});
      ok = false;
      continue;
    }
    es.reinits.push_back({static_cast<uint32_t>(slot),
                          ctx.div(apply(r.value), sign), apply(r.fired)});
  }
  return ok;
}

std::unique_ptr<Pass> createEventsPass() {
  return std::make_unique<EventsPass>();
}

} // namespace ldae::passes
