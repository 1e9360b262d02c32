// The lowered form every code generator consumes: a DaeSystem turned once
// into straight-line functions (a topological list of scalar operations plus
// the stores that write the function's outputs). The LLVM emitter, the C
// printer and the interpreter all walk this same plan, so they cannot
// disagree about what is computed, in which order, or which row a domain
// error names. See docs/codegen.md for the semantics of every operation.
#pragma once

#include "ir/DaeSystem.h"
#include "support/Expected.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ldae {
class SourceManager;
}

namespace ldae::codegen {

/// One scalar operation. Leaves (Const ... Cj) read an input; they are cheap
/// and re-materialized wherever used, so they never cross a chunk boundary.
enum class OpCode : uint8_t {
  Const,  // value
  LoadY,  // y[index]
  LoadYp, // yp[index]
  LoadP,  // p[index]
  Time,   // t
  Cj,     // the Jacobian's cj (Jacobian functions only)
  Add,    // a + b
  Sub,    // a - b
  Mul,    // a * b
  Div,    // a / b            check: b == 0
  Neg,    // -a
  PowInt, // a ^ index, index >= 1, by square-and-multiply (powIntSteps)
  Pow,    // pow(a, b)        check: (a < 0 && b not integer) || (a == 0 && b < 0)
  Sqrt,   // sqrt(a)          check: a < 0
  Func1,  // sub = FuncKind   check: log/log10 !(a > 0), asin/acos |a| > 1
  Func2,  // sub = FuncKind   check: mod b == 0
  Select, // a != 0 ? b : c   (error bit of the branch taken only)
  Compare,// sub = CompareKind, 1 or 0
  And,    // (a != 0 && b != 0), 1 or 0 (b's error bit only when a != 0)
  Or,     // (a != 0 || b != 0), 1 or 0 (b's error bit only when a == 0)
  Not,    // a == 0, 1 or 0
  Reduce, // a folded with reduction `index`: a ± term(0) ± term(1) ...
          // in that order (the error bit: a's or any term's)
  ExtArg, // argument `index` of an external call: value a; b is argument
          // index - 1 (an ExtArg node; b == a for argument 0)
  ExtCall,// output `value` of CodePlan::externals[index] at the arguments
          // of the ExtArg chain ending in a (no arguments: a is no ExtArg);
          // sub == 1: called only where b != 0, 0 elsewhere (a branch of
          // an if not taken); sub == 0: always, b == a
};

/// True for the leaves that read inputs or constants.
inline bool isLeaf(OpCode op) { return op <= OpCode::Cj; }

/// Number of operands (a, b, c in order) an operation reads.
inline unsigned numOperands(OpCode op) {
  switch (op) {
  case OpCode::Neg:
  case OpCode::PowInt:
  case OpCode::Sqrt:
  case OpCode::Func1:
  case OpCode::Not:
  case OpCode::Reduce:
    return 1;
  case OpCode::Select:
    return 3;
  default:
    return isLeaf(op) ? 0 : 2;
  }
}

struct PlanNode {
  OpCode op = OpCode::Const;
  uint8_t sub = 0;       // FuncKind or CompareKind
  bool checks = false;   // this operation has a domain check
  bool mayFail = false;  // its error bit can be set (own check or operands)
  uint32_t a = 0, b = 0, c = 0; // operand node indices
  int32_t index = 0;     // LoadY/LoadYp/LoadP slot; PowInt exponent
  double value = 0;      // Const

  uint32_t operand(unsigned i) const { return i == 0 ? a : i == 1 ? b : c; }
};

/// out<array>[index] = value of `node`; a set error bit makes the function
/// return 1 + row (the first such store in order wins).
struct PlanStore {
  uint32_t node = 0;
  uint8_t array = 0; // 0: first output array, 1: second (init Jacobian Jyp)
  uint32_t index = 0;
  uint32_t row = 0;
  /// Runs right after this node (>= node, nondecreasing over the stores),
  /// so values are written as soon as they are ready and stay in order.
  uint32_t after = 0;
};

/// The C ABI signature a function implements.
enum class FnSig {
  Values,       // int f(double t, y, yp, p, double *out)
  Jacobian,     // int f(double t, y, yp, p, double cj, double *out)
  InitJacobian, // int f(double t, y, yp, p, double *out0, double *out1)
  State,        // int f(double t, y, p, double *out): over t and y only
                // (the geometric slots; yp reads are a lowering error)
};

/// A contiguous range of nodes compiled into one machine function, with the
/// stores it performs. Bounded size keeps compile time linear.
struct PlanChunk {
  uint32_t nodeBegin = 0, nodeEnd = 0;
  uint32_t storeBegin = 0, storeEnd = 0;
};

struct PlanLoop;

/// The ExtArg nodes of external call `call` in argument order.
std::vector<uint32_t> externalArguments(std::span<const PlanNode> nodes,
                                        uint32_t call);

/// An external function wrapper the plan calls (ir/External.h): every
/// backend calls it as `void symbol(const double *in, double *out)`.
struct PlanExternal {
  std::string symbol;
  std::string name; // the Modelica name, for messages
  unsigned numInputs = 0, numOutputs = 0;
  /// Where the loaded wrapper is in this process (0 when not loaded: the
  /// C emitter needs only the symbol).
  uintptr_t address = 0;
  /// The shared objects an emitted program links for it, in load order.
  std::vector<std::string> objects;
};

struct PlanFunction {
  std::string name; // symbol suffix: "residual_0", "jac_csc_1", "outputs"...
  FnSig sig = FnSig::Values;
  std::vector<PlanNode> nodes; // operands before users
  std::vector<PlanStore> stores;
  uint32_t zeroFill[2] = {0, 0}; // elements of out0/out1 zeroed first (dense)
  std::vector<PlanChunk> chunks;   // at least one
  /// Per node: slot in the function's scratch array holding its value (and
  /// at slot + 1 its error bit when mayFail) when a later chunk uses it; -1
  /// otherwise.
  std::vector<int32_t> spill;
  uint32_t numSpillSlots = 0;
  /// Stores of one repeated shape, computed by loops after the straight-line
  /// part above (see PlanLoop). Run only while no error has been returned.
  std::vector<PlanLoop> loops;
  /// The loops Reduce nodes run: long sums of terms of one shape.
  std::vector<PlanLoop> reductions;
  /// CodePlan::externals again, for the interpreter, which runs one
  /// function without its plan (empty when no node calls one).
  std::vector<PlanExternal> externals;
};

/// An index that changes from one loop iteration to the next: base + i *
/// stride, or table[i] when the instances are not evenly spaced.
struct IndexColumn {
  int64_t base = 0, stride = 0;
  std::vector<int32_t> table; // empty: affine
  bool affine() const { return table.empty(); }
  int64_t at(uint32_t i) const {
    return affine() ? base + int64_t(i) * stride : table[i];
  }
};

/// `count` stores whose expressions have the same shape, computed by one
/// loop (docs/codegen.md, "Loops"): iteration i evaluates `body`, a plan
/// function of one chunk in which every LoadY/LoadYp/LoadP index and every
/// store's index and row name a column, read at i. Compile time then
/// depends on the number of shapes, not on the number of equations.
///
/// A reduction (PlanFunction::reductions) has a body without stores: the
/// value of its last node is added to the accumulator of its Reduce node,
/// or subtracted when `subtract` is set.
struct PlanLoop {
  uint32_t count = 0;
  PlanFunction body;
  std::vector<IndexColumn> columns;
  bool subtract = false;
};

struct StateSetPlan {
  std::vector<int> isDifferential;
  int residual = -1, jacobianDense = -1, jacobianCsc = -1, pivot = -1;
  int pivotSize = 0;
  std::vector<int> colptr, rowind; // CSC pattern of dF/dy + cj dF/dy'
  std::string description;
};

/// The events block of the C ABI (ldae_model, ABI 6; docs/events.md) as
/// tables plus the plan functions that compute it (EventPlan.h fills it).
/// Every table empty and every function -1 for a model without events.
struct EventPlan {
  std::vector<std::string> discreteNames;
  std::vector<double> discreteStart;
  std::vector<int> discreteKind; // LDAE_DISCRETE_*
  std::vector<int> rootRelation; // per root; empty without discrete values
  std::vector<int> reinitTarget;
  std::vector<std::string> terminateMessage;
  /// out = [new discrete values | reinit values | reinit fired |
  /// terminate fired] (ldae_model::event_update).
  int update = -1;
  std::vector<int> thresholdRelation, sampleDiscrete;
  /// out = [thresholds | start, interval of each sample, in pairs |
  /// source, delay time, maximum of each delay, in threes].
  int timeEvents = -1;
  std::vector<std::string> assertMessage, assertOrigin;
  std::vector<int> assertLevel;
  /// Assert i's message values are out[n_asserts + assertValueBegin[i]
  /// ...] of the asserts function (n_asserts + 1 entries).
  std::vector<int> assertValueBegin;
  int asserts = -1; // out = 1 (holds) or 0 per assert, then message values
  std::vector<int> modeDiscrete;
  std::vector<double> modeValues;
  /// Per state set, n entries each; empty: NULL in the ABI.
  std::vector<std::vector<int>> dummyOf, originalRow;

  unsigned numDiscrete() const { return discreteNames.size(); }
};

/// A block whose states the runtime chooses (ldae_dynamic_set).
struct DynamicSetPlan {
  int rows = 0, forced = 0, candidates = 0;
  int jacobian = -1, values = -1; // functions
  int param = 0;
  std::vector<double> start;
  std::vector<int> stateSlots;
  std::vector<std::string> names;
};

/// Everything the C ABI struct holds, as plain data plus plan functions.
struct CodePlan {
  std::string name;       // the model's name
  /// The external functions ExtCall nodes call, by their `index`.
  std::vector<PlanExternal> externals;
  std::string symbolName; // a C identifier derived from it
  std::vector<PlanFunction> functions;
  std::vector<StateSetPlan> stateSets;
  std::vector<DynamicSetPlan> dynamicSets;
  /// Entries of p past the pre() values: the selection matrices.
  unsigned selectionCount = 0;
  int initResidual = -1, initJacobian = -1, roots = -1, outputs = -1,
      drift = -1;
  /// The model as written (ldae_model::written_residual, the geometric
  /// methods with events): its rows and dense Jacobian parts.
  int writtenResidual = -1, writtenJacobian = -1;
  unsigned nWritten = 0;
  /// dG/dy and dG/dy' of the initial equations in one CSC pattern.
  int initJacobianCsc = -1;
  std::vector<int> initColptr, initRowind;

  unsigned n = 0, nInit = 0, nRoots = 0, nOutputs = 0, nDrift = 0;
  std::vector<std::string> varNames, paramNames, outputNames, residualOrigin;
  std::vector<std::string> outputOrigin; // empty, or one per output
  /// The Results block (ldae_model::output_unit...): one per output / per
  /// parameter, "" where the model gives none.
  std::vector<std::string> outputUnit, outputDescription, paramUnit,
      paramDescription;
  std::vector<int> outputAlias;
  bool explicitOde = false; // ldae_model::explicit_ode
  /// The geometric slots (--method sga|ode): n_ode = n when the system is
  /// linearly implicit, with the constraints c(t, y) and dc/dy (dense,
  /// nConstraints x n, column-major).
  unsigned nOde = 0, nConstraints = 0;
  int constraints = -1, constraintJacobian = -1;
  bool projectConstraints = false; // ldae_model::project_constraints
  bool algebraicErrorTest = true; // ldae_model::algebraic_error_test
  /// ldae_model::tested: values, nominal values, dz/dy (FnSig::Jacobian at
  /// cj = 0) in a CSC pattern; -1 / empty when there are none.
  int tested = -1, testedJacobianCsc = -1;
  std::vector<double> testedNominal;
  std::vector<int> testedColptr, testedRowind;
  std::vector<double> startY, startYp, nominal, paramValues;
  std::vector<int> fixed;
  double startTime, stopTime, tolerance, interval; // NaN when unset

  /// Parameter bindings, for runs that change a parameter without
  /// recompiling (ldae_model::bind: runtime::simulate's params, the
  /// emitted main's --param). `bind` (FnSig::Values; -1 when nothing is
  /// bound) writes the
  /// binding of boundParams[j] at out[j], then the start value of unknown
  /// boundStarts[k] at out[boundParams.size() + k], each over the current
  /// p. Applying the parameter part bindPasses times settles every chain of
  /// bindings.
  int bind = -1;
  std::vector<int> boundParams, boundStarts;
  unsigned bindPasses = 0;
  /// Per parameter: 1 if its value fixed the model's structure at compile
  /// time (directly or through a parameter bound to it), 2 for a constant
  /// (ldae_model::param_structural).
  std::vector<int> structuralParams;

  /// External objects (MLS 12.9.7) for a program of its own (--emit c):
  /// `objects` (FnSig::Values; -1 when there are none) calls the
  /// constructor of parameter objectParams[j] over p and writes the new
  /// handle at out[j], made before anything runs. `unmadeObject` names a
  /// handle with no constructor call to make it again ("" when none).
  int objects = -1;
  std::vector<int> objectParams;
  std::string unmadeObject;
  /// The impure calls made when compiling (ir::Model::compileTimeCalls),
  /// made again by such a program before its objects, for their effects
  /// on the C code's state.
  struct Replay {
    PlanExternal external; // symbol, objects, outputs
    std::vector<double> inputs;
  };
  std::vector<Replay> replays;

  EventPlan events;

  /// Entries of the p every function reads: the parameters, then each
  /// discrete value and each pre() value (ldae_model's events block), then
  /// the selection matrices of the dynamic sets.
  size_t pSize() const {
    return paramValues.size() + 2 * size_t(events.numDiscrete()) +
           selectionCount;
  }
};

/// "file:line:col" of `loc`, or `none` when it is unknown or there is no
/// source manager to name its file.
std::string sourceOrigin(const SourceManager *sources, const SourceLoc &loc,
                         const char *none);

/// Removes nodes no store reaches and renumbers the rest (order kept).
void removeDeadNodes(PlanFunction &fn);

/// Square-and-multiply schedule for x^k (k >= 1) that every backend follows
/// so results agree bit for bit: see PowInt.
struct PowIntStep {
  bool multiplyResult; // result = result ? result * base : base
  bool squareBase;     // then base = base * base
};
/// The steps of one exponent, in a fixed array (k < 2^31 takes at most 31):
/// the interpreter follows it on every evaluation, without allocating.
struct PowIntSchedule {
  std::array<PowIntStep, 32> steps;
  unsigned size = 0;
  const PowIntStep *begin() const { return steps.data(); }
  const PowIntStep *end() const { return steps.data() + size; }
};
PowIntSchedule powIntSteps(int32_t k);

/// The C math library function computing built-in `f` ("sin", "fabs",
/// "atan2"...), or null for those lowered inline (sign, min, max, mod).
const char *cMathName(ir::FuncKind f);

/// The threshold rule shared with the runtime (LDAE_DENSE_THRESHOLD).
bool useDenseJacobian(unsigned n);

/// The exported symbol of plan function `fn`: "<symbolName>_<fn.name>".
std::string functionSymbol(const CodePlan &plan, const PlanFunction &fn);

/// Operations in the plan, loop and reduction bodies counted once: what
/// compile time grows with.
size_t planNodes(const CodePlan &plan);

/// Operations one call of every plan function performs, loop and reduction
/// bodies counted once per iteration: what the cost of an evaluation grows
/// with (`--jit auto` decides by it).
size_t planWork(const CodePlan &plan);

} // namespace ldae::codegen
