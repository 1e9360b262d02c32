// The index-1 system handed to code generation: what the runtime integrates.
// Produced by the pass pipeline from a Model (after alias elimination, index
// reduction and dummy derivatives); consumed by the LLVM emitter, the C
// emitter and the interpreter alike, which all fill the same C ABI
// (runtime/include/ldae/model.h).
//
// Layout rule. The unknown vector y holds `unknowns[i]`, each standing for
// the IR node Variable(var, order). In residuals:
//   Variable(var, order)       of unknowns[i]           reads y[i]
//   Variable(var, order + 1)   of a differential unknown reads y'[i]
// A dummy derivative is an algebraic unknown with order >= 1 (it stands for
// der(x) itself); the variable it differentiates is then algebraic too.
#pragma once

#include "ir/Model.h"

#include <functional>
#include <string>
#include <vector>

namespace ldae::ir {

struct SystemUnknown {
  VarKey key;          // the IR node Variable(key) this slot holds
  std::string name;    // `x`, `der(x)` for a dummy derivative
  bool differential = false;
  double start = 0;    // start value of y[i]
  ExprRef startBinding = nullptr; // `start` over parameters (null: literal)
  double startDerivative = 0; // start value of y'[i]
  double nominal = 1;
  bool fixed = false;  // start value is a condition (fixed = true)
  SourceLoc loc;
};

/// One choice of states for dynamic state selection: its own residuals and
/// differential flags over the same unknown layout.
struct StateSet {
  std::vector<ExprRef> residuals;  // size n
  std::vector<bool> differential;  // size n
  /// m×m matrix (column-major) whose conditioning tells how well this set
  /// fits: the Jacobian of the differentiated constraints w.r.t. the
  /// derivatives this set makes dummies. Empty for a static set.
  unsigned pivotSize = 0;
  std::vector<ExprRef> pivot;
  std::vector<std::string> states; // names, for reports
  /// Optional per-set meaning of the unknown slots: keys[i] replaces
  /// unknowns[i].key in this set's residuals, Jacobian and pivot (dynamic
  /// dummy derivatives: slot 5 holds der(y) in one set, der(x) in another).
  /// Empty: every slot keeps unknowns[i].key. Outputs, roots, initial
  /// residuals and constraints always use unknowns[i].key.
  std::vector<VarKey> keys;
};

/// An unknown of the index-1 system that the causal form computes outside
/// the integrator: the error test still controls it (ldae_model::tested).
struct TestedValue {
  ExprRef value = nullptr; // over y, y' as the layout rule says
  double nominal = 1;
};

/// A reported variable computed from the unknowns (aliases, solved-out).
/// What a reported value is (ldae_model's Results block, result files).
enum class OutputKind { Continuous, Derivative, Discrete };

struct SystemOutput {
  std::string name;
  ExprRef value = nullptr; // over y, y' as the layout rule says
  SourceLoc loc; // the equation computing it (causalization), if any
  OutputKind kind = OutputKind::Continuous;
  std::string unit, description; // the declaration's; "" where none
  /// 0, or +(j + 1) / -(j + 1) when alias elimination made this variable
  /// equal to output j / to minus output j (a result file stores the
  /// column once and refers to it with sign).
  int alias = 0;
};

/// What a discrete value is (ldae_model::discrete_kind, LDAE_DISCRETE_*).
enum class DiscreteKind {
  Variable, Relation, When, Sample, Initial, Terminal, Delay
};

/// One value of the discrete state. Continuous expressions read its current
/// value as Parameter(parameterValues.size() + k) and its pre() value as
/// Parameter(parameterValues.size() + discrete.size() + k) (ParamIds past
/// the model's own parameters; ldae_model's p layout).
struct DiscreteValue {
  std::string name;  // the variable's name, or the relation as lsd text
  DiscreteKind kind = DiscreteKind::Variable;
  double start = 0;  // before the initial event
};

/// `reinit(x, value)`: y[unknown] becomes `value` where `fired` is 1.
struct ReinitUpdate {
  uint32_t unknown = 0;
  ExprRef value = nullptr; // over the layout (pre() of x reads y[unknown])
  ExprRef fired = nullptr;
};

struct TerminateUpdate {
  ExprRef fired = nullptr;
  std::string message;
};

struct AssertCheck {
  ExprRef condition = nullptr; // 1 holds, 0 fails
  std::string message; // with placeholders of messageValues (MessageText.h)
  int level = 0; // 0 error, 1 warning
  SourceLoc loc;
  std::vector<ExprRef> messageValues;
};

/// `delay(e, d, dMax)` of an e that changes at events only: the discrete
/// value `discrete` takes, d after each event, e's value after it. source
/// reads only parameters and discrete values; time and max (d again in
/// the two-argument form) only parameters.
struct DelayInput {
  ExprRef source = nullptr, time = nullptr, max = nullptr;
  uint32_t discrete = 0;
};

/// The event part of a system (docs/events.md; ldae_model's ABI 6 fields).
/// Every expression is over the layout rule, like outputs.
struct EventSystem {
  std::vector<DiscreteValue> discrete;
  /// The new value of each discrete value (size discrete.size()), the
  /// event update of ldae_model: relations from y, discrete equations
  /// inlined in dependency order, when-assignments `if fired then e else
  /// pre(v)`; sample/initial/terminal values copy their current value.
  std::vector<ExprRef> update;
  /// For each entry of DaeSystem::roots, the relation it switches.
  std::vector<uint32_t> rootRelation;
  std::vector<ReinitUpdate> reinits;
  std::vector<TerminateUpdate> terminates;
  /// Time relations: threshold (over parameters and discrete values) and
  /// the relation's discrete index.
  std::vector<ExprRef> timeThresholds;
  std::vector<uint32_t> thresholdRelation;
  /// sample(start, interval): its discrete index.
  std::vector<std::pair<ExprRef, ExprRef>> samples;
  std::vector<uint32_t> sampleDiscrete;
  /// delay() of values that change at events (docs/events.md, "delay()"),
  /// in the order of their discrete values.
  std::vector<DelayInput> delays;
  std::vector<AssertCheck> asserts;
  /// Variable structure: the discrete values choosing this mode's
  /// branches, and the values this system was built for.
  std::vector<uint32_t> modeDiscrete;
  std::vector<double> modeValues;

  bool empty() const { return discrete.empty() && asserts.empty(); }
};

/// A block whose states are chosen at run time (ldae_dynamic_set): its
/// states s = A c are unknowns of their own (differential), A a 0/1
/// selection of the candidates c read from the parameter vector, and the
/// residuals s - A c and s' - A c' hold in every state set.
struct DynamicStateSet {
  unsigned rows = 0, forced = 0, candidates = 0;
  /// rows x (forced + candidates), column-major: the block's equations
  /// differentiated by its columns, forced ones first.
  std::vector<ExprRef> jacobian;
  /// 2 * candidates: each candidate's value, then its derivative (the
  /// dummy derivative slot).
  std::vector<ExprRef> values;
  std::vector<std::string> names; // candidates
  /// A: (candidates - rows + forced) x candidates, column-major, from
  /// ParamId `param` on; its value at the start.
  ParamId param = 0;
  std::vector<double> start;
  std::vector<VarKey> states; // s_k, one unknown each
};

/// What shape the residual has, which decides how the runtime integrates
/// it. One of them: a system is never both an explicit ODE and the SGA's
/// linearly implicit field.
enum class SystemForm {
  /// F(t, y, y') = 0, index 1 (or the model's own index under --method
  /// raw): IDA.
  Implicit,
  /// Row i of the only state set is der(unknown i) - f_i(t, y) (the causal
  /// form "ODE"; ldae_model::explicit_ode).
  ExplicitOde,
  /// `--method sga|ode`: the SGA's vector field on P_f. Every unknown is
  /// differential; stateSets[0] (the only set) has n rows linear in y',
  /// A(t, y) y' - alpha(t, y), with dF/dy' nonsingular on P_f; and
  /// `constraints` holds every constraint generation (over t and y only).
  /// The runtime integrates y' = A^-1 alpha with CVODE.
  LinearlyImplicit,
};

struct DaeSystem {
  std::shared_ptr<ExprContext> ctx;
  const Model *model = nullptr; // names, parameters, locations
  std::vector<SystemUnknown> unknowns;
  /// State sets; stateSets[0] is the initial choice. Always at least one.
  std::vector<StateSet> stateSets;
  /// Conditions that must hold only at the start (initial equations),
  /// over y and y'.
  std::vector<ExprRef> initialResiduals;
  /// The geometric methods' system only (ldae_model::written_residual):
  /// the model's equations as written and the link rows, over the same
  /// unknowns, whose pencil an event re-initializes along. Empty otherwise.
  std::vector<ExprRef> writtenResiduals;
  /// Constraints of the original model the reduced one must keep
  /// (their largest residual is reported as drift).
  std::vector<ExprRef> constraints;
  /// Root functions for events: lhs - rhs of each relation on continuous
  /// unknowns (events.rootRelation says which).
  std::vector<ExprRef> roots;
  std::vector<SystemOutput> outputs;
  /// Source location of the equation behind each residual row.
  std::vector<SourceLoc> residualLocs;
  std::vector<double> parameterValues;
  std::vector<std::string> parameterNames;
  SystemForm form = SystemForm::Implicit;
  /// With SystemForm::LinearlyImplicit: project onto `constraints` after
  /// each step (sga); false shows the drift (ode). A flag, not a form: sga
  /// and ode hand over the same system and differ only in what the runtime
  /// does after a step.
  bool projectOntoConstraints = false;
  /// The differential index of the system as handed to the integrator: 1
  /// when reduced, the model's own under `--method raw`.
  int index = 1;
  /// The causalized unknowns, in assignment order (empty before causalize).
  std::vector<TestedValue> tested;
  /// Events and the discrete state (empty for a purely continuous model).
  EventSystem events;
  /// The jump rule's pencil of the model as written (ldae_model::dummy_of,
  /// original_row): per state set, the slot each dummy derivative slot
  /// differentiates (-1: none), and whether each residual row is an
  /// equation as written. Empty: no dummies, every row original.
  std::vector<std::vector<int>> dummyOf;
  std::vector<std::vector<bool>> originalRow;
  /// Run-time state selection of large blocks; their selection matrices
  /// take the parameter vector's entries past the discrete values' (from
  /// the first set's `param` on, selectionCount in all).
  std::vector<DynamicStateSet> dynamicSets;
  unsigned selectionCount = 0;
};

/// Calls `f` on every expression of the event system (to rewrite it where
/// a pass rewrites the system's other expressions).
void forEachEventExpr(EventSystem &ev, const std::function<void(ExprRef &)> &f);
/// The expressions of the event system (to walk what it reads).
std::vector<ExprRef> eventExprs(const EventSystem &ev);
/// Renumbers the reinit targets after unknowns were removed or moved:
/// newIndex[old] is the new index, -1 for a removed unknown (then false).
bool renumberReinits(EventSystem &ev, const std::vector<int> &newIndex);

/// Whether slot i of state set `set` is differential (a set without its
/// own flags uses unknowns[i].differential).
std::vector<bool> setDifferential(const DaeSystem &sys, size_t set);
/// Whether slot i is differential in any state set: the flags under which
/// outputs, roots and initial residuals are read.
std::vector<bool> anyDifferential(const DaeSystem &sys);

/// The layout rule, the one place it is written: calls
/// `visit(key, slot, derivative)` for each Variable node an expression may
/// read, slot i's own key (keys[i], or unknowns[i].key when `keys` is
/// empty) reading y[i], then the next order of each differential slot
/// reading y'[i]. Own keys come first: where a key appears twice, the first
/// visit wins.
template <typename Visit>
void forEachLayoutRead(const DaeSystem &sys, const std::vector<VarKey> &keys,
                       const std::vector<bool> &differential, Visit &&visit) {
  auto key = [&](size_t i) { return keys.empty() ? sys.unknowns[i].key : keys[i]; };
  for (size_t i = 0; i < sys.unknowns.size(); ++i)
    visit(key(i), static_cast<uint32_t>(i), false);
  for (size_t i = 0; i < sys.unknowns.size(); ++i)
    if (differential[i])
      visit(VarKey{key(i).var, key(i).order + 1}, static_cast<uint32_t>(i),
            true);
}

} // namespace ldae::ir
