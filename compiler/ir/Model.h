// A flat model: scalar variables and parameters, and equations `residual = 0`
// over one expression DAG. The frontend produces it; passes transform it;
// every variable and equation keeps where the user wrote it.
#pragma once

#include "ir/ExprContext.h"
#include "ir/Print.h"
#include "support/SourceManager.h"

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace ldae::ir {

enum class StateSelect { Never, Avoid, Default, Prefer, Always };
const char *stateSelectName(StateSelect s); // "never", ... as in lsd

/// A built-in call the frontend keeps as a discrete variable for the events
/// pass (which turns it into a discrete value of the matching kind). Its
/// name is the call as written (`initial()`, `sample(0, 0.1)`) and prints
/// verbatim.
/// Delay: `delay(e, d)` of an `e` that changes only at events, set by the
/// runtime to e's value d seconds earlier (docs/events.md, "delay()").
enum class EventInput : uint8_t { None, Initial, Terminal, Sample, Delay };

/// A scalar unknown. Its derivatives are Variable nodes of higher order.
struct Variable {
  std::string name;      // flat name as the user sees it: `x`, `r1.v`, `m[2].s`
  std::string component; // component path it came from ("" at top level)
  SourceLoc loc;         // its declaration
  double start = 0;
  bool hasStart = false;
  bool fixed = false;
  double nominal = 1;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  StateSelect stateSelect = StateSelect::Default;
  /// The `start` expression when it reads parameters (null for a literal):
  /// an emitted program re-evaluates it when a parameter is changed.
  ExprRef startBinding = nullptr;
  /// A `start` that reads unknowns (parameters with fixed = false) and is
  /// no condition (fixed = false): a guess, evaluated from their start
  /// values once those are known (frontend/InitialGuesses.cpp).
  ExprRef startGuess = nullptr;
  std::string unit;
  std::string description; // the declaration's string comment, "" if none
  bool isInput = false;
  bool isOutput = false;
  bool isDiscrete = false; // Integer/Boolean variables, changed only at events
  bool isInteger = false;  // declared Integer (printed as such)
  bool isBoolean = false;  // declared Boolean (printed as such)
  EventInput input = EventInput::None;
  /// Made by the compiler, not written in the model (the value of a step
  /// function the events pass keeps at its crossings): never reported.
  bool generated = false;
  ExprRef sampleStart = nullptr, sampleInterval = nullptr; // input Sample
  /// input Delay: the delayed expression, the delay time and the maximum
  /// delay (null in the two-argument form), as written.
  ExprRef delayed = nullptr, delayTime = nullptr, delayMax = nullptr;
};

/// A parameter or constant: a value fixed for a run.
struct Parameter {
  std::string name;
  std::string component;
  SourceLoc loc;
  double value = 0;
  bool isConstant = false; // `constant`: cannot be overridden
  std::string unit;        // "" when the declaration gives none
  std::string description; // the declaration's string comment, "" if none
  bool isInteger = false;
  bool isBoolean = false;
  /// An external object's handle (MLS 12.9.7): a pointer valid in the
  /// process that called its constructor (`binding`), not a number.
  bool externalObject = false;
  /// The binding expression when it reads other parameters (null for a
  /// literal or a command-line override): `value` is its value, and an
  /// emitted program re-evaluates it when a parameter it reads is changed.
  ExprRef binding = nullptr;
  /// The value fixed the model's structure at compile time (an array size,
  /// a branch chosen, a subscript): it cannot change without recompiling.
  bool structural = false;
  /// A value of the discrete state the events pass appended after the
  /// user's parameters (DaeSystem::events): not overridable, not a
  /// parameter of the compiled model, never folded as a constant.
  bool discrete = false;
  /// Made by the compiler for the runtime (homotopy.lambda), not the user's:
  /// not reported among the outputs.
  bool generated = false;
};

/// Where an equation came from, for messages and for alias elimination.
enum class EquationOrigin {
  Declared,       // written in an equation section
  Binding,        // `Real e = expr;` declaration binding
  Connection,     // potential equality of a connection set
  FlowSum,        // flows of a connection set sum to zero
  UnconnectedFlow,// a flow of a connector nobody connected is zero
  Initial,        // an `initial equation`
  Differentiated, // made by index reduction from `parent`
};

struct Equation {
  ExprRef residual = nullptr; // the equation is residual = 0 (lhs - rhs)
  SourceLoc loc;              // the equation (or declaration) in the source
  std::string component;      // component path it came from
  EquationOrigin origin = EquationOrigin::Declared;
  std::string text;           // the source text as written, for messages
};

/// `reinit(v, value)` inside a when-clause.
struct Reinit {
  VarId var = 0;
  ExprRef value = nullptr;
  SourceLoc loc;
};

/// `terminate("message")` inside a when-clause.
struct Terminate {
  std::string message;
  SourceLoc loc;
};

/// `assert(condition, "message", level)` in an equation section.
struct Assert {
  ExprRef condition = nullptr;
  std::string message; // with placeholders of messageValues (MessageText.h)
  int level = 0; // 0 error, 1 warning (AssertionLevel.error / .warning)
  SourceLoc loc;
  /// What String() of an unknown shows in the message, at the failure.
  std::vector<ExprRef> messageValues;
};

/// `when condition then ... end when;`: kept on the model for the event stage.
struct WhenClause {
  ExprRef condition = nullptr; // fires when it turns from 0 to 1
  /// The elements of a vector condition (`when {a, b}`), else the
  /// condition alone: the clause fires when any element turns from 0 to 1
  /// (Modelica 3.5 section 8.3.5), not only when their disjunction does.
  std::vector<ExprRef> elements;
  SourceLoc loc;
  /// An `elsewhen` branch of the clause before it: it fires only where no
  /// earlier branch of the same when-equation fires.
  bool elsewhen = false;
  std::vector<Reinit> reinits;
  std::vector<Equation> equations; // discrete assignments `v = expr`
  /// The left side of each of `equations` (a Variable node).
  std::vector<ExprRef> targets;
  std::vector<Terminate> terminates;
  /// Checked where the clause fires (the events pass makes each a
  /// discrete value the clause assigns and an assert of it).
  std::vector<Assert> asserts;
};

/// The `experiment` annotation; unset fields take the driver's defaults.
struct Experiment {
  std::optional<double> startTime, stopTime, tolerance, interval;
};

class Model : public NameResolver {
public:
  explicit Model(std::shared_ptr<ExprContext> ctx = std::make_shared<ExprContext>())
      : ctx_(std::move(ctx)) {}

  ExprContext &ctx() const { return *ctx_; }
  std::shared_ptr<ExprContext> sharedCtx() const { return ctx_; }

  std::string name;
  SourceLoc loc;
  std::vector<Variable> variables;
  std::vector<Parameter> parameters;
  std::vector<Equation> equations;
  std::vector<Equation> initialEquations;
  std::vector<WhenClause> whenClauses;
  std::vector<Assert> asserts;
  /// The homotopy() calls with a simplified model, by the If node they were
  /// lowered to: (actual, simplified), for printing the flat model.
  std::unordered_map<ExprRef, std::pair<ExprRef, ExprRef>> homotopies;
  Experiment experiment;
  /// The impure external calls made when compiling (a parameter's value,
  /// under initial() alone), in the order made: their effects on the C
  /// code's own state (MSL's initializeImpureRandom seeds the generator
  /// impureRandom draws from) are made again by a program of its own
  /// (--emit c) before it runs.
  struct CompileTimeCall {
    std::string symbol;               // the wrapper (ir/External.h)
    std::vector<std::string> objects; // as ExternalFunction::objects
    std::vector<double> inputs;
    unsigned outputs = 0;
  };
  std::vector<CompileTimeCall> compileTimeCalls;

  VarId addVariable(Variable v);
  ParamId addParameter(Parameter p);
  std::optional<VarId> findVariable(const std::string &name) const;
  std::optional<ParamId> findParameter(const std::string &name) const;
  /// Current parameter values, indexed by ParamId.
  std::vector<double> parameterValues() const;
  /// The user's parameters: those before the discrete slots the events
  /// pass appends.
  size_t userParameterCount() const;
  /// Whether each parameter fixes the structure: marked structural by the
  /// frontend, or read by the binding of one that is (a new value of
  /// either needs a recompile).
  std::vector<bool> structuralParameters() const;

  /// The user's spelling of Variable(key): `x`, `der(x)`, `der(der(x))`.
  std::string variableName(VarKey key) const;
  // NameResolver
  std::string variableName(VarId v) const override;
  std::string parameterName(ParamId p) const override;
  const std::pair<ExprRef, ExprRef> *homotopyOf(ExprRef e) const override;
  bool verbatimVariable(VarId v) const override;
  bool verbatimParameter(ParamId p) const override;

  /// Prints the whole model as lsd (the `--emit flat` format).
  std::string print() const;

private:
  std::shared_ptr<ExprContext> ctx_;
  // Name indexes, built on the first lookup: the frontend adds every
  // variable of a large model and never looks one up, and a hash map of
  // strings is a large part of flattening.
  mutable std::unordered_map<std::string, VarId> varIndex_;
  mutable std::unordered_map<std::string, ParamId> paramIndex_;
  mutable size_t varsIndexed_ = 0, paramsIndexed_ = 0;
};

} // namespace ldae::ir
