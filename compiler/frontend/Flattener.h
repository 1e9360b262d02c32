// The flattener: turns the AST of the chosen model into an ir::Model. One
// class holds the state of one compilation; its member functions live in
// several files by responsibility:
//   Lookup.cpp       names: component references, package constants, classes
//   Instantiate.cpp  instance tree: extends, modifiers, types, arrays, parameters
//   Lower.cpp        expressions -> IR (operators, arrays, reductions, builtins)
//   Inline.cpp       user functions inlined at their calls
//   FlattenEquations.cpp  equations incl. for/if/when, bindings
//   Connections.cpp  connection sets -> equations
// Errors are reported as they are found and evaluation continues where it
// can, so one run reports several problems; results are then discarded.
#pragma once

#include "frontend/Ast.h"
#include "frontend/ClassTable.h"
#include "frontend/Frontend.h"
#include "frontend/Value.h"
#include "ir/Differentiate.h"
#include "ir/External.h"
#include "ir/Model.h"
#include "support/Diagnostics.h"

#include <functional>
#include <map>
#include <set>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace ldae::frontend {

struct InstNode;

/// Where an expression is evaluated: the instance whose components it sees
/// (null inside functions and packages) and the class it is written in
/// (for classes, package constants and imports).
struct Scope {
  InstNode *inst = nullptr;
  const ast::ClassDef *cls = nullptr;
};

/// A function value (MLS 12.4.2.1): a function and the inputs a partial
/// application bound, their values lowered where it was written.
struct FunctionValue {
  const ast::ClassDef *fn = nullptr;
  std::vector<std::pair<std::string, Value>> bound;
};

/// One input's argument of a call: a value, or a function value for an
/// input of a function type; neither where the input's default applies.
struct CallArgument {
  std::optional<Value> value;
  std::optional<FunctionValue> function;
  /// Bound by a partial application: the call's own arguments skip it.
  bool preBound = false;
};

/// Local names: for-iterators, function inputs, outputs and locals.
struct Env {
  Env *parent = nullptr;
  std::vector<std::pair<std::string, Value>> vars;
  /// Where the statements run so far left the innermost loop (`break`)
  /// or the function (`return`): null never, else a condition (1: on
  /// every path). A later assignment takes effect only where neither
  /// holds.
  ir::ExprRef breaking = nullptr, returning = nullptr;

  /// The inputs of a function type: their function values.
  std::vector<std::pair<std::string, FunctionValue>> functions;

  Value *find(const std::string &name);
  void set(const std::string &name, Value v);
  const FunctionValue *findFunction(const std::string &name) const;
};

/// A modification merged from declarations, extends clauses and the
/// instantiating component; outer ones win.
struct Mod;
using ModPtr = std::shared_ptr<const Mod>;
struct Mod {
  const ast::Expr *value = nullptr;
  std::string text; // `name = value` as written, for binding equations
  SourceLoc loc; // of the value
  uint32_t length = 1;
  SourceLoc nameLoc; // of the modified name, `x` in `x(start = 1)`
  uint32_t nameLength = 1;
  Scope scope;                // where `value` is evaluated
  std::vector<int64_t> index; // 1-based element of `value` to take
  bool each = false;
  /// `redeclare Type name(...)`: the declaration that replaces the
  /// modified component's (its modifiers are among `subs`), written in
  /// `redeclareScope`.
  const ast::Component *redeclare = nullptr;
  Scope redeclareScope;
  std::vector<std::pair<std::string, ModPtr>> subs;

  ModPtr sub(const std::string &name) const;
};

/// An external function's wrapper that returns its String result.
using ExternalStringEntry = const char *(*)(const double *in, double *out);

/// Whether `e` is `initial()` (CompileTimeCalls.cpp).
bool isInitialCall(const ast::Expr &e);

/// Whether `fn` is loadResource, which ldaec answers (LoadResource.cpp).
bool isLoadResource(const ast::ClassDef &fn);

/// `outer` over `inner`: outer's value wins; sub-modifiers merge by name.
ModPtr mergeMods(const ModPtr &outer, const ModPtr &inner);

enum class BuiltinType { None, Real, Integer, Boolean, String };

/// One scalar of a Real/Integer/Boolean component: a variable or parameter.
struct Slot {
  bool isParam = false;
  uint32_t id = 0; // VarId or ParamId
};

/// One component instance (or the model itself at the root).
struct InstNode {
  std::string name; // as declared ("r1"); array elements "m[2]"
  std::string path; // flat prefix ("c.r1", "m[2]"); "" for the root
  InstNode *parent = nullptr;
  const ast::Component *decl = nullptr;
  const ast::ClassDef *declClass = nullptr; // class the declaration is in
  ModPtr mod;

  /// Prepared: a class instance whose members exist, not yet elaborated
  /// (a reference through it, `tr.VectorGroup`, elaborates only the
  /// member it names, so bindings between two instances in both
  /// directions are no cycle).
  enum class State { Declared, Elaborating, Prepared, Done, Failed };
  State state = State::Declared;
  bool membersReady = false; // class instance: members exist (may be unelaborated)

  // Resolved type.
  const ast::ClassDef *cls = nullptr; // long class of a class instance
  BuiltinType builtin = BuiltinType::None;
  /// An enumeration type: the component is an Integer leaf whose values
  /// are its literals' positions, 1 ... n (MLS 4.9.5's Integer(e)).
  const ast::ClassDef *enumeration = nullptr;
  /// An external object's handle (a Real leaf, ExternalObject.h).
  bool externalObject = false;
  std::string typeName;
  bool isConnector = false;
  bool flow = false;
  ast::Variability variability = ast::Variability::Continuous;
  ast::Causality causality = ast::Causality::None;
  std::vector<int64_t> dims;

  /// Component arrays: the elements, row-major.
  std::vector<std::unique_ptr<InstNode>> elements;
  /// Class instances: members in declaration order, inherited first, with
  /// distinct names.
  std::vector<std::unique_ptr<InstNode>> members;
  /// Name -> member, only for classes of many members: most instances
  /// (pins, resistors) have a few, which a scan finds faster than a hash
  /// map costs to build, and a large model has hundreds of thousands.
  std::unordered_map<std::string, InstNode *> memberIndex;
  static constexpr size_t kMemberScanLimit = 8;

  /// The member named `name` (for an `outer` member, the `inner` one it
  /// refers to), or null.
  InstNode *findMember(const std::string &name) const {
    InstNode *m = nullptr;
    if (members.size() <= kMemberScanLimit) {
      for (const auto &c : members)
        if (c->name == name) {
          m = c.get();
          break;
        }
    } else if (auto it = memberIndex.find(name); it != memberIndex.end()) {
      m = it->second;
    }
    return m && m->inner ? m->inner : m;
  }
  /// An `outer` component: the `inner` one of its name in the nearest
  /// enclosing instance that has one (MLS 5.4); it has no variables itself.
  InstNode *inner = nullptr;
  /// A member of an expandable connector (ExpandableConnectors.cpp):
  /// connectable whatever its type, present only when connected.
  bool inExpandable = false;
  /// An `inner outer` component linked to an inner above: it is that
  /// outer to its own instance's equations, and this separate instance of
  /// its declaration, with its modifiers, is the inner of the components
  /// below (MLS 5.4; MSL's CompositeStep reports its suspend and resume to
  /// its steps through it). Null otherwise.
  std::unique_ptr<InstNode> innerHalf;
  /// Conditional members whose condition is false (MLS 4.4.5): removed
  /// with the connect equations that name them; kept for the message
  /// that any other use gets.
  std::vector<std::unique_ptr<InstNode>> removed;
  /// The removed conditional member named `name`, or null.
  const InstNode *findRemoved(const std::string &name) const {
    for (const auto &m : removed)
      if (m->name == name)
        return m.get();
    return nullptr;
  }
  /// Appends a member whose name no member has.
  void addMember(std::unique_ptr<InstNode> m) {
    members.push_back(std::move(m));
    if (members.size() == kMemberScanLimit + 1)
      for (const auto &old : members)
        memberIndex.emplace(old->name, old.get());
    else if (members.size() > kMemberScanLimit + 1)
      memberIndex.emplace(members.back()->name, members.back().get());
  }
  /// Equations of the class instance with the class they are written in.
  std::vector<std::pair<const ast::Equation *, const ast::ClassDef *>>
      equations, initialEquations;
  /// Its algorithm and initial algorithm sections, likewise.
  std::vector<std::pair<const std::vector<ast::Statement> *,
                        const ast::ClassDef *>>
      algorithms, initialAlgorithms;
  /// Builtin leaves: one slot per scalar element, row-major.
  std::vector<Slot> slots;
  /// Binding equation of a variable leaf (`Real e = expr`), if any.
  ModPtr binding;
  /// `parameter Real p(fixed = false)`: an unknown constant, a variable
  /// with der(p) = 0 whose value the initialization finds; its binding is
  /// an initial equation.
  bool initialParameter = false;

  bool isArray() const { return !dims.empty(); }
  bool isLeaf() const { return builtin != BuiltinType::None; }
  bool isParameterLike() const {
    return !initialParameter &&
           (variability == ast::Variability::Parameter ||
            variability == ast::Variability::Constant);
  }
};

/// What a component reference denotes: values, or (for connect) components.
struct RefTarget {
  InstNode *node = nullptr; // class instance, or leaf with `slot`
  int64_t slot = -1;
};
/// A subscript whose value is known only at run time: the dimension at
/// `axis` of the selection (whole so far) and the 1-based index choosing
/// one of its `size` elements.
struct RunTimeSubscript {
  size_t axis = 0;
  int64_t size = 0;
  ir::ExprRef index = nullptr;
  std::string what; // the array as written
  SourceRange where;
};

struct Selection {
  std::vector<int64_t> shape;
  std::vector<RefTarget> targets;
};

class Flattener {
public:
  Flattener(ClassTable &classes, DiagnosticEngine &diags,
            const FrontendOptions &opts);
  ~Flattener();

  /// Flattens class `cls`; nullptr after errors.
  std::unique_ptr<ir::Model> flatten(const ast::ClassDef &cls);

  // ----- Lookup.cpp
  /// The value of a component reference expression.
  std::optional<Value> lowerRef(const ast::Expr &ref, const Scope &scope,
                                Env *env);
  /// The components a reference denotes (for connect).
  std::optional<Selection> selectComponents(const ast::Expr &ref,
                                            const Scope &scope, Env *env);
  /// Suggestion text for an undefined name, "" if none is close.
  std::string suggest(const std::string &name, const Scope &scope, Env *env);
  /// "undefined name" for the first part of `ref`, with a suggestion.
  void reportUndefined(const ast::Expr &ref, const Scope &scope, Env *env);
  /// The enumeration class `e` names (a type name, through short classes:
  /// `type Init = Modelica.Blocks.Types.Init`), or null; reports nothing.
  const ast::ClassDef *enumerationNamed(const ast::Expr &e,
                                        const Scope &scope);
  /// The enumeration `cls` is, through short classes, or null.
  const ast::ClassDef *enumerationOf(const ast::ClassDef *cls);
  /// A use of a conditional component that its condition removed.
  void reportRemoved(const InstNode &removed, SourceRange range);
  /// Whether the component reference `ref` goes through a conditional
  /// component that its condition removed (its connect equations go too).
  bool namesRemoved(const ast::Expr &ref, const Scope &scope);

  // ----- Instantiate.cpp
  bool ensureElaborated(InstNode &node, SourceLoc usedAt);
  /// Only the members of a class instance (of every element of an
  /// array): enough to step through it to one of them.
  bool ensureMembers(InstNode &node, SourceLoc usedAt);
  /// Moves the conditional members whose condition is false to
  /// InstNode::removed.
  void removeDisabledMembers(InstNode &node);
  /// Links each `outer` member to its `inner` component (an error when
  /// there is none).
  void linkOuterMembers(InstNode &node);

  // ----- Lower.cpp
  std::optional<Value> lower(const ast::Expr &e, const Scope &scope, Env *env);
  /// The message of assert or terminate: a String expression ("..." +
  /// String(p)) with a value when compiling.
  std::optional<std::string> messageText(const ast::Expr &message,
                                         const char *what, const Scope &scope,
                                         Env *env);
  /// String(x, significantDigits = 6, minimumLength = 0, leftJustified =
  /// true) and String(x, format = "...") of a value known when compiling
  /// (StringCalls.cpp).
  std::optional<Value> lowerStringCall(const ast::Expr &call,
                                       const Scope &scope, Env *env);
  /// `e` as a number known at compile time (parameters allowed);
  /// `what` names the use in the error ("array size", "subscript").
  std::optional<double> evalConstant(const ast::Expr &e, const Scope &scope,
                                     Env *env, const std::string &what);
  std::optional<int64_t> evalInteger(const ast::Expr &e, const Scope &scope,
                                     Env *env, const std::string &what);
  /// The numeric value of a lowered scalar that must not depend on
  /// variables or time; nullopt if it does (nothing reported). When it does
  /// not but has no value (0/0), `evalError` (if given) gets the reason.
  std::optional<double> constantValue(ir::ExprRef e,
                                      std::string *evalError = nullptr);
  /// The value of a parameter binding or a `start` attribute: like
  /// constantValue, but the parameters it reads stay changeable (see
  /// ir::Parameter::structural).
  std::optional<double> bindingValue(ir::ExprRef e,
                                     std::string *evalError = nullptr) {
    readingBinding_ = true;
    std::optional<double> v = constantValue(e, evalError);
    readingBinding_ = false;
    return v;
  }
  /// The value of a modifier (its element `mod.index`); memoized.
  std::optional<Value> lowerModValue(const Mod &mod);
  /// `for` iterator ranges: the values of `range`, which must be constant.
  std::optional<std::vector<double>> iteratorValues(const ast::ForIndex &it,
                                                    const Scope &scope,
                                                    Env *env);

  // ----- Builtins.cpp
  std::optional<Value> lowerCall(const ast::Expr &call, const Scope &scope,
                                 Env *env);
  /// Every output of a call (user functions; one value for built-ins).
  ir::ExprRef emptyMinMax(const std::string &name);
  std::optional<std::vector<Value>> lowerCallOutputs(const ast::Expr &call,
                                                     const Scope &scope,
                                                     Env *env);

  /// Element-wise application; map2Value broadcasts scalars and reports
  /// (at `where`, naming `op`) when the shapes disagree.
  Value map1Value(const Value &a,
                  const std::function<ir::ExprRef(ir::ExprRef)> &f);
  std::optional<Value>
  map2Value(const Value &a, const Value &b,
            const std::function<ir::ExprRef(ir::ExprRef, ir::ExprRef)> &f,
            const ast::Expr &where, const char *op);

  // ----- Inline.cpp
  /// `given`: the inputs' arguments already lowered (where a call's own
  /// argument is missing, the input's default applies); without it the
  /// call's arguments are lowered here.
  std::optional<std::vector<Value>>
  inlineCall(const ast::ClassDef &fn, const ast::Expr &call,
             const Scope &scope, Env *env,
             const std::vector<CallArgument> *given = nullptr);
  /// The function value argument `e` denotes for an input of a function
  /// type: a partial application `function f(a = 1)`, a function's name,
  /// or an input of the caller that holds one.
  std::optional<FunctionValue> functionArgument(const ast::Expr &e,
                                                const Scope &scope, Env *env);
  /// The function class `type` (read in `in`) names, or null.
  const ast::ClassDef *functionTypeOf(const ast::Name &type,
                                      const ast::ClassDef &in);
  /// A call whose arguments have the dimensions `over` more than their
  /// inputs declare (MLS 12.4.6): the function applied to each element,
  /// its outputs arrays of `over` and their own shape.
  std::optional<std::vector<Value>>
  vectorizedCall(const ast::ClassDef &fn, const ast::Expr &call,
                 const Scope &scope, Env *env,
                 const std::vector<const ast::Component *> &inputs,
                 const std::vector<CallArgument> &args,
                 const std::vector<int64_t> &over);
  /// A function's variables, each with the class that declares it (bases
  /// first, MLS 12.2), and the class whose algorithm (or external clause)
  /// is its body.
  struct FunctionParts {
    std::vector<const ast::Component *> comps;
    std::vector<const ast::ClassDef *> owner;
    const ast::ClassDef *body = nullptr;
  };
  std::optional<FunctionParts> functionParts(const ast::ClassDef &fn,
                                             SourceRange where);
  /// Whether `type`, read in `in`, is Real, Integer, Boolean or an
  /// enumeration, through short classes.
  bool isNumericType(const ast::Name &type, const ast::ClassDef &in);

  // ----- CompiledFunctions.cpp
  /// The outputs of function `fn` computed by its body compiled to C and
  /// called at run time, for the inputs bound in `fenv` (its other
  /// variables there give their shapes); `at` is the call.
  std::optional<std::vector<Value>> compiledCall(const ast::ClassDef &fn,
                                                 const FunctionParts &parts,
                                                 const Env &fenv,
                                                 SourceRange at);
  /// Set, with nothing reported, where a function's statements cannot run
  /// symbolically but can at run time (a while-condition that reads
  /// variables, a loop past the statement budget): inlineCall compiles
  /// the function instead.
  bool compileInstead_ = false;

  // ----- ExternalFunctions.cpp
  /// The outputs of external function `fn` with its inputs bound in `fenv`
  /// (and its outputs there, unassigned, giving their shapes).
  std::optional<std::vector<Value>> externalCall(const ast::ClassDef &fn,
                                                 Env &fenv);

  // ----- LoadResource.cpp
  /// loadResource(uri): the file name a URI names (MLS 13.5).
  std::optional<Value> lowerLoadResource(const ast::Expr &call,
                                         const Scope &scope, Env *env);

  // ----- CompileTimeCalls.cpp
  /// A call of impure external function `fn` (wrapper `entry`, inputs
  /// `in`): made once, now, where a parameter's value is computed (see
  /// ImpureContext); its outputs are constants. `made` (the wrapper's
  /// symbol and objects) is recorded with the inputs in the model.
  std::optional<std::vector<Value>>
  impureCall(const ast::ClassDef &fn, ir::ExternalEntry entry,
             ir::Model::CompileTimeCall made,
             const std::vector<ir::ExprRef> &in,
             const std::vector<const ast::Component *> &outputs,
             const std::map<const ast::Component *, size_t> &outOffset,
             size_t numOut, Env &fenv, SourceRange at);
  /// A call of external function `fn` returning a String (`returned`):
  /// made now, the text and the other outputs constants.
  std::optional<std::vector<Value>>
  stringCall(const ast::ClassDef &fn, ExternalStringEntry entry,
             const std::vector<ir::ExprRef> &in,
             const std::vector<const ast::Component *> &outputs,
             const ast::Component *returned,
             const std::map<const ast::Component *, size_t> &outOffset,
             size_t numOut, Env &fenv, SourceRange at);
  /// Whether the call of `fn` just made raised no ModelicaError; else
  /// reports its message at `at`.
  bool succeeded(const ast::ClassDef &fn, SourceRange at);
  /// The values of `in` now, or a located error naming `fn`.
  std::optional<std::vector<double>>
  argumentsNow(const ast::ClassDef &fn, const std::vector<ir::ExprRef> &in,
               SourceRange at);
  /// `outputs` as constants from `out`.
  std::vector<Value>
  constantOutputs(const std::vector<const ast::Component *> &outputs,
                  const std::map<const ast::Component *, size_t> &outOffset,
                  const std::vector<double> &out, Env &fenv);
  /// While one lives, the flattener computes a parameter's value, or what
  /// a branch under `initial()` alone computes (`when initial() then`,
  /// `if initial() then` in an algorithm): the places an impure function
  /// may be called, once, when compiling (CompileTimeCalls.cpp).
  struct ImpureContext {
    Flattener &f;
    explicit ImpureContext(Flattener &f) : f(f) { ++f.impureContext_; }
    ~ImpureContext() { --f.impureContext_; }
  };
  /// While one lives, the flattener lowers the body of a when-clause that
  /// fires during the run: an impure function is called there at run time
  /// (ExternalFunctions.cpp, "run-time impure calls"), each call site once
  /// per firing, in the order written: each call reads the previous one's
  /// first output (`impureToken_`), so none is made before it.
  struct FiringContext {
    Flattener &f;
    ir::ExprRef savedToken;
    explicit FiringContext(Flattener &f) : f(f), savedToken(f.impureToken_) {
      ++f.firingContext_;
      f.impureToken_ = nullptr;
    }
    ~FiringContext() {
      --f.firingContext_;
      f.impureToken_ = savedToken;
    }
  };
  /// Whether a call of `fn` (its entry `f`) is small enough to compile;
  /// else an error at `at`.
  bool externalCallFits(const ast::ClassDef &fn, const ir::ExternalFunction &f,
                        SourceRange at);
  /// After a when-clause's body: when none of its equations reads its last
  /// run-time impure call (a call made for what it does), adds one that
  /// does, so the call is made where the clause fires.
  void keepImpureCalls(ir::WhenClause &clause);

  /// Reports through the engine once per (diagnostic, location, text):
  /// a class instantiated many times reports its error once.
  Diagnostic &report(DiagId id, SourceRange range,
                     std::vector<std::string> args = {});
  Diagnostic &report(DiagId id, SourceLoc loc,
                     std::vector<std::string> args = {}) {
    return report(id, SourceRange{loc, 1}, std::move(args));
  }

  ir::ExprContext &ctx() { return model_->ctx(); }
  /// The discrete variable standing for initial(), terminal() or a
  /// sample(start, interval) call (one per distinct call text).
  ir::ExprRef eventInput(ir::EventInput kind, const std::string &text,
                         ir::ExprRef start, ir::ExprRef interval,
                         SourceLoc loc);
  ir::Model &model() { return *model_; }
  /// The parameter `homotopy.lambda` (1: the actual model) that every
  /// homotopy() with a simplified model blends by; made on first use.
  ir::ParamId homotopyLambda();
  DiagnosticEngine &diags() { return diags_; }
  ClassTable &classes() { return classes_; }

private:
  friend class EquationFlattener;
  friend class FunctionTranslator;
  friend class ConnectionBuilder;

  // Instantiate.cpp
  void elaborateInstance(InstNode &node);
  /// Collects the members of a class instance with their modifiers
  /// (state stays as it is); elaborateMembers elaborates each.
  void prepareInstance(InstNode &node);
  void elaborateMembers(InstNode &node);
  void elaborateComponent(InstNode &node, bool membersOnly);
  /// A Prepared instance (or array of them) elaborated to Done.
  void finishPrepared(InstNode &node);
  bool resolveType(InstNode &node);
  void createLeafSlots(InstNode &node);
  bool isInitialParameter(const InstNode &node);
  /// Whether `node` has `fixed = false`.
  bool fixedFalse(const InstNode &node);
  /// An Integer or Boolean parameter with fixed = false takes its initial
  /// equation `p = expr` as its binding (Instantiate.cpp).
  void adoptInitialEquation(InstNode &node);
  /// Parameters whose value failed (reported): what reads them is not
  /// reported again.
  std::set<ir::ParamId> failedParameters_;
public:
  bool readsFailedParameter(ir::ExprRef e) const;
private:
  /// The variables of parameters with fixed = false (initialParameter).
  std::set<ir::VarId> initialParameterVars_;
  /// Initial equations that became a parameter's binding, per instance.
  std::set<std::pair<const InstNode *, const ast::Equation *>>
      adoptedInitialEquations_;
  void createParameter(InstNode &node, const std::string &name,
                       const ModPtr &mod);
  void createVariable(InstNode &node, const std::string &name,
                      const ModPtr &mod);
  /// The `unit` attribute of `mod` ("" when absent; a number is reported).
  std::string readUnit(const ModPtr &mod, const std::string &name);
  void checkModifiers(InstNode &node);
  ModPtr makeMod(const ast::Modification *m, const Scope &scope);
  void checkUsedVersions(const ast::ClassDef &cls);
  void readExperiment(const ast::ClassDef &cls, InstNode &root);
  /// Adds `count` instances of `node` to the total; false (reported once,
  /// at `node`) past kMaxInstances.
  bool countInstances(int64_t count, const InstNode &node);

  // Inline.cpp
  enum class ExecResult { Ok, Error };
  /// Runs statements symbolically: a function body (`scope` without an
  /// instance) or a model's algorithm section (`scope` the instance); the
  /// assigned names are locals in `env`, other names are looked up in
  /// `scope`.
  ExecResult execStatements(const std::vector<ast::Statement> &list,
                            const ast::ClassDef &fn, const Scope &scope,
                            Env &env);
  ExecResult execIf(const ast::Statement &st, size_t branch,
                    const ast::ClassDef &fn, const Scope &scope, Env &env);
  bool assign(const ast::Expr &target, Value value, const ast::ClassDef &fn,
              const Scope &scope, Env &env);
  /// A model's algorithm section: executed once symbolically, each
  /// variable it assigns gets one equation `v = its final value`.
  void flattenAlgorithm(const std::vector<ast::Statement> &section,
                        const Scope &scope, bool initial = false);
  /// A when-statement at the top level of a model's algorithm section: a
  /// when-clause whose equations assign the statement's targets.
  ExecResult execWhenStatement(const ast::Statement &st,
                               const ast::ClassDef &fn, const Scope &scope,
                               Env &env);
  /// While a model's algorithm section runs: the names its when-statements
  /// assign (they get no `v = final value` equation); null otherwise.
  std::vector<std::string> *algorithmWhenTargets_ = nullptr;
  /// Loops around the statement being run (a `break` outside one is an
  /// error).
  int loopDepth_ = 0;
  /// Where the statements so far left (break or return), or null.
  ir::ExprRef exitedOf(const Env &env);
  /// Runs one iteration's body of a loop: false when every path has left
  /// the loop (break or return) and it must stop.
  bool continueLoop(Env &env);
  /// While a model's algorithm section runs: the names it assigns (locals
  /// that pre() looks past); null otherwise.
  const std::vector<std::string> *algorithmLocals_ = nullptr;
  size_t statementBudget_ = 0;

  // FlattenEquations.cpp
  /// Where flattened equations go: the model's equations or initial
  /// equations, or the discrete assignments of a when-clause.
  struct EqSink {
    std::vector<ir::Equation> *out = nullptr;
    ir::WhenClause *when = nullptr;
    ir::EquationOrigin origin = ir::EquationOrigin::Declared;
    bool inVariableIf = false;
    /// Inside a variable if-equation: when its branch is the one taken
    /// (null outside one).
    ir::ExprRef branchTaken = nullptr;
  };
  /// While an assert's message is lowered: the values String() of
  /// unknowns shows in it, at run time (null elsewhere: refused).
  std::vector<ir::ExprRef> *messageValues_ = nullptr;
  void flattenInstance(InstNode &node);
  /// The connect equations of the whole instance tree, before any other
  /// equation, so that cardinality() counts them all (Cardinality.cpp).
  void collectConnects(InstNode &node);
  /// While collectConnects runs: only connect equations (and the for- and
  /// if-equations around them) are flattened.
  bool connectSweep_ = false;
  /// After it: the connect equations are in, the main sweep skips them.
  bool connectsCollected_ = false;
  /// How many connect equations name each connector instance.
  std::unordered_map<const InstNode *, int> connectCount_;
  /// cardinality(c) (MLS 3.7.2.3): the number of connect equations that
  /// name connector c, a constant.
  std::optional<Value> lowerCardinality(const ast::Expr &call,
                                        const Scope &scope, Env *env);
  void flattenBinding(InstNode &leaf);
  void flattenEquation(const ast::Equation &eq, const Scope &scope, Env *env,
                       EqSink &sink);
  void flattenIf(const ast::Equation &eq, const Scope &scope, Env *env,
                 EqSink &sink);
  void flattenIfInWhen(const ast::Equation &eq,
                       const std::vector<ir::ExprRef> &conds,
                       const std::vector<const std::vector<ast::Equation> *> &branches,
                       const Scope &scope, Env *env, EqSink &sink);
  void flattenWhen(const ast::Equation &eq, const Scope &scope, Env *env,
                   EqSink &sink);
  void flattenCallEquation(const ast::Equation &eq, const Scope &scope,
                           Env *env, EqSink &sink);
  void flattenAssert(const ast::Equation &eq, const Scope &scope, Env *env,
                     EqSink &sink);
  void addEquation(EqSink &sink, ir::ExprRef lhs, ir::ExprRef rhs,
                   const ast::Equation &eq,
                   const Scope &scope);

  // Connections.cpp
  struct ConnectPair {
    ir::VarId a = 0, b = 0;
    bool flow = false;
    bool aOutside = false, bOutside = false;
    SourceLoc loc;
    std::string text, component;
  };
  void addConnect(const ast::Equation &eq, const Scope &scope, Env *env);

  // RecordBindings.cpp
  /// A record component's value as bindings of its fields.
  void bindRecordValue(InstNode &node);
  ModPtr fieldBinding(const Mod &whole, const std::string &field,
                      const ast::Expr *value, const Scope &scope);
  /// The references `field` in the record a binding names.
  std::vector<std::unique_ptr<ast::Expr>> recordFieldRefs_;

  // ExpandableConnectors.cpp
  /// The expandable connector instance and the member name a reference
  /// `bus.name` denotes when the connector has no such member yet.
  std::pair<InstNode *, std::string>
  missingExpandableMember(const ast::Expr &ref, const Scope &scope);
  /// Adds member `name` to expandable connector `bus`, of the type of
  /// `like` with sizes `dims`.
  InstNode *addExpandableMember(InstNode &bus, const std::string &name,
                                const InstNode &like,
                                const std::vector<int64_t> &dims);
  /// A connect equation of the sweep before the connect equations: adds
  /// the members it names to expandable connectors.
  void augmentConnect(const ast::Equation &eq, const Scope &scope, Env *env);
  /// The unions of connected expandable connectors; the members never
  /// present removed.
  void completeExpandableConnectors();
  /// Expandable connector instances, as prepared.
  std::vector<InstNode *> expandables_;
  /// Pairs of expandable connectors connected to each other.
  std::vector<std::pair<InstNode *, InstNode *>> busPairs_;
  /// Declarations of the members connects added.
  std::vector<std::unique_ptr<ast::Component>> addedBusMembers_;
  /// While the sweep for expandable connectors runs.
  bool expandSweep_ = false;
  bool pairConnectors(const RefTarget &a, const RefTarget &b,
                      const ast::Equation &eq, const Scope &scope,
                      bool aOutside, bool bOutside);
  void buildConnectionEquations();
  std::vector<ConnectPair> connectPairs_;
  std::vector<ir::VarId> flowVars_; // flow variables of connectors

  // Lookup.cpp
  /// With `runTime`, the last part's subscripts on an array of values may
  /// be known only at run time (see applySubscripts).
  std::optional<Selection>
  resolveInstancePath(const ast::Expr &ref, size_t firstPart, InstNode *start,
                      const Scope &scope, Env *env,
                      std::vector<RunTimeSubscript> *runTime = nullptr);
  std::optional<Value> packageConstant(const ast::Component &comp,
                                       const ast::ClassDef &owner,
                                       const ast::Expr &ref, size_t part,
                                       const Scope &scope, Env *env);
  /// Applies subscripts `subs` to an array of shape `dims`. With
  /// `runTime`, a scalar subscript known only at run time (an Integer or
  /// enumeration unknown) keeps its dimension whole and is recorded there
  /// for selectAtRunTime; without it, such a subscript is an error.
  bool applySubscripts(const std::vector<ast::ExprPtr> &subs,
                       const std::vector<int64_t> &dims, const std::string &what,
                       const Scope &scope, Env *env,
                       std::vector<int64_t> &outShape,
                       std::vector<int64_t> &outOffsets, SourceLoc loc,
                       std::vector<RunTimeSubscript> *runTime = nullptr);
  /// Collapses each recorded dimension of `v` to the element its run-time
  /// subscript selects (frontend/RunTimeSubscripts.cpp).
  Value selectAtRunTime(Value v, const std::vector<RunTimeSubscript> &runTime);
  /// The assignment `slot[offsets] := value` whose subscripts `runTime`
  /// are known only at run time: each element of the kept dimensions
  /// takes `value` where the indices pick it, keeps its value elsewhere
  /// (frontend/RunTimeSubscripts.cpp). `write` stores one element.
  void assignAtRunTime(const Value &value, const std::vector<int64_t> &shape,
                       const std::vector<int64_t> &offsets,
                       const std::vector<RunTimeSubscript> &runTime,
                       Value &slot,
                       const std::function<void(ir::ExprRef &, ir::ExprRef)>
                           &write);
  /// The assert that `sub`'s index is within 1..size where the branches
  /// being lowered are taken (branchGuard_, statementGuard_).
  void indexInRange(const RunTimeSubscript &sub, int64_t size);
  /// While an if-expression's branch is lowered: the condition that takes
  /// it (and the enclosing branches'); null outside any.
  ir::ExprRef branchGuard_ = nullptr;
  /// While an if-statement's branch (on variables) runs: the conditions
  /// that take it; null outside any.
  ir::ExprRef statementGuard_ = nullptr;
  /// While a when-clause's body is lowered: its asserts, checked where it
  /// fires (a subscript there is used only then); null outside any.
  std::vector<ir::Assert> *whenAsserts_ = nullptr;
  struct WhenAssertsScope {
    Flattener &f;
    std::vector<ir::Assert> *saved;
    WhenAssertsScope(Flattener &f, std::vector<ir::Assert> *into)
        : f(f), saved(f.whenAsserts_) {
      f.whenAsserts_ = into;
    }
    ~WhenAssertsScope() { f.whenAsserts_ = saved; }
  };
  /// Whether `index` can only take integer values: it reads no Real
  /// unknown and not time.
  bool isIntegerValued(ir::ExprRef index);

public:
  /// Limits against adversarial input (each reported once, then the
  /// flattening stops adding): elements of one array, scalars in total,
  /// component instances in total (an instance costs far more memory than
  /// a scalar: 25 levels of two components each would be 2^25 of them;
  /// only instances of classes count, leaves count as scalars),
  /// inlining depth, instance nesting (components in components, extends
  /// chains and short-type chains; elaboration recurses once per level and
  /// flat names grow with the depth). docs/frontend.md, "Limits".
  static constexpr int64_t kMaxArrayElements = 2'000'000;
  static constexpr size_t kMaxScalars = 4'000'000;
  static constexpr size_t kMaxInstances = 1'000'000;
  static constexpr unsigned kMaxInlineDepth = 64;
  static constexpr unsigned kMaxInstanceDepth = 1000;

  /// True once a size limit was hit: flattening stops producing.
  bool overBudget();
  /// Index of `d` in the end-of-dimension stack used by `end` in subscripts.
  std::vector<int64_t> endStack;
  unsigned inlineDepth = 0;
  unsigned lowerDepth = 0;

private:
  ClassTable &classes_;
  DiagnosticEngine &diags_;
  const FrontendOptions &opts_;
  std::unique_ptr<ir::Model> model_;
  std::unique_ptr<ir::Differentiator> diff_;
  std::unique_ptr<InstNode> root_;
  /// The inner components added at the top for outer ones that have none
  /// (MLS 5.4), by name, with the class they were added for.
  struct AddedInner {
    std::unique_ptr<InstNode> node;
    const ast::ClassDef *cls = nullptr;
  };
  std::map<std::string, AddedInner> addedInners_;
  /// The inner added at the top for `outer` component `m`, or null when
  /// another outer of its name has another class (reported).
  InstNode *addedInner(const InstNode &m);
  /// --param and --override values by name (`p`, `x.start`): value, used.
  std::map<std::string, std::pair<double, bool>> overrides_;
  /// Reports the overrides that named nothing (exit 2 in the driver).
  void reportUnusedOverrides();
  /// The suffix of an override that sets a variable's start value.
  static constexpr const char *kStartSuffix = ".start";
  std::map<const ast::Component *, Value> packageConstants_;
  std::map<const ast::Component *, bool> packageConstantBusy_;
  std::map<std::tuple<const ast::Expr *, InstNode *, const ast::ClassDef *>,
           Value>
      modValueCache_;
  bool budgetReported_ = false;
  size_t instances_ = 0; // component instances created, array elements each
  bool readingBinding_ = false; // see bindingValue
  int impureContext_ = 0;        // see ImpureContext
  int firingContext_ = 0;        // see FiringContext
  ir::ExprRef impureToken_ = nullptr; // see FiringContext
  uint64_t impureTokenSite_ = 0;      // the call site impureToken_ is of
  uint64_t impureSites_ = 0;     // run-time impure call sites so far
  std::set<std::string> reported_;
  Diagnostic dropped_;

public:
  /// The instance being elaborated or flattened while it lives: a
  /// diagnostic in another file than the model's (a library class) gets a
  /// note per instance level down to the model, as Clang's "in
  /// instantiation of".
  class InstanceContext {
  public:
    InstanceContext(Flattener &f, const InstNode *node)
        : f_(f), saved_(f.instanceContext_) {
      f.instanceContext_ = node;
    }
    ~InstanceContext() { f_.instanceContext_ = saved_; }
    InstanceContext(const InstanceContext &) = delete;
    InstanceContext &operator=(const InstanceContext &) = delete;

  private:
    Flattener &f_;
    const InstNode *saved_;
  };

private:
  const InstNode *instanceContext_ = nullptr;
  void addInstanceNotes(Diagnostic &d);

public:
  ir::Differentiator &differentiator() { return *diff_; }
  const std::vector<std::string> &attributeNames(BuiltinType t) const;
};

/// Whether `eq` is a connect equation or holds one (in a for- or
/// if-equation).
bool containsConnect(const ast::Equation &eq);

/// Flat name of element `index` (0-based, row-major) of an array of `dims`:
/// `x[2]`, `A[1,3]`.
std::string elementName(const std::string &base, const std::vector<int64_t> &dims,
                        int64_t index);
/// The 1-based subscripts of row-major `index`.
std::vector<int64_t> elementSubscripts(const std::vector<int64_t> &dims,
                                       int64_t index);

} // namespace ldae::frontend
