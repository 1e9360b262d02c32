// The abstract syntax tree of an lsd file, built from the ANTLR parse tree by
// AstBuilder. Every node keeps its source location; equations and
// declarations also keep their source text for messages. The tree is
// immutable after building: the flattener reads it, never changes it.
#pragma once

#include "support/SourceManager.h"

#include <memory>
#include <string>
#include <vector>

namespace ldae::frontend::ast {

struct Expr;
using ExprPtr = std::unique_ptr<Expr>;
struct Modification;
struct Name;
using ModificationPtr = std::unique_ptr<Modification>;

enum class ExprKind {
  Number,  // number
  String,  // text
  Bool,    // boolean
  Ref,     // component reference: parts
  Call,    // name(args [for iterators]); der/initial/pure keep their name
  Binary,  // ops[0] binOp ops[1]
  Sum,     // ops[0] +- ops[1] +- ...: `negated[k]` for a minus before ops[k]
  Unary,   // unOp ops[0]
  If,      // ops = cond, then, {cond, then}, else
  Array,   // {ops...} or {ops[0] for iterators}
  Matrix,  // [rows...]
  Range,   // ops = start, [step,] stop
  Tuple,   // (a, b): ops may hold nullptr for omitted outputs
  End,     // `end` inside a subscript
  Colon,   // `:` as a subscript
};

enum class BinOp {
  Add, Sub, Mul, Div, Pow,          // matrix forms
  EAdd, ESub, EMul, EDiv, EPow,     // element-wise .+ .- .* ./ .^
  Lt, Le, Gt, Ge, Eq, Ne, And, Or,
};
enum class UnOp { Neg, Plus, Not };

/// One `name[subscripts]` of a component reference `a[1].b.c[i, j]`.
struct RefPart {
  std::string name;
  std::vector<ExprPtr> subscripts;
};

/// `i in range` of a for-equation, reduction or array constructor; a null
/// range means "deduce from use", which lsd does not support.
struct ForIndex {
  std::string name;
  ExprPtr range;
  SourceLoc loc;
};

/// A call argument, positional when `name` is empty.
struct Arg {
  std::string name;
  ExprPtr value;
};

struct Expr {
  ExprKind kind = ExprKind::Number;
  SourceLoc loc;
  uint32_t length = 1; // columns to underline (same line only)

  double number = 0;       // Number
  bool boolean = false;    // Bool
  std::string text;        // String; Call: function name as written
  bool global = false;     // Ref/Call: leading '.'
  std::vector<RefPart> parts; // Ref; Call: the function name's parts
  BinOp binOp = BinOp::Add;
  UnOp unOp = UnOp::Neg;
  std::vector<ExprPtr> ops;
  std::vector<bool> negated;              // Sum
  std::vector<Arg> args;                  // Call
  /// Call: `function f(a = 1)` as an argument, a function value with `a`
  /// bound (MLS 12.4.2.1); the call made where the value is called.
  bool partialApplication = false;
  std::vector<ForIndex> iterators;        // Call (reduction), Array
  std::vector<std::vector<ExprPtr>> rows; // Matrix

  /// The reference as written: `a[...].b` (subscripts elided).
  std::string refName() const;
  /// Call: the function's name as a Name (where written, the callee's
  /// length underlined).
  Name calleeName() const;

  Expr() = default;
  Expr(Expr &&) = default;
  Expr &operator=(Expr &&) = default;
  /// Iterative: a chain of 300,000 products nests that deep, and the
  /// default recursive destruction would overflow the stack.
  ~Expr();
};

/// A modifier `[each] [final] name.path(mods) = value "comment"`.
struct Component;

struct Modifier {
  bool each = false;
  bool final = false;
  std::vector<std::string> path;
  /// `redeclare Type name(mods)`: the new declaration of `name` (MLS 7.3).
  std::shared_ptr<Component> redeclared;
  SourceLoc loc;
  uint32_t length = 1;
  std::string text; // as written, for binding equations
  ModificationPtr mod; // may be null: `name` alone
};

/// `(args) = value`; either part may be absent.
struct Modification {
  std::vector<Modifier> args;
  ExprPtr value;
  SourceLoc loc;
};

enum class Variability { Continuous, Discrete, Parameter, Constant };
enum class Causality { None, Input, Output };

struct TypePrefix {
  bool flow = false;
  bool stream = false;
  Variability variability = Variability::Continuous;
  Causality causality = Causality::None;
};

/// A dotted name `A.B.C` as written, with where it was written.
struct Name {
  std::vector<std::string> parts;
  bool global = false;
  SourceLoc loc;
  uint32_t length = 1;
  std::string str() const;
};

/// One declared component: `Real x[3](start = 0) = y "doc";` Declarations
/// with several declarators become several Components sharing the type.
struct Component {
  std::string name;
  SourceLoc loc;
  uint32_t length = 1;
  std::string text; // the declarator as written: `x[3](start = 0) = y`
  TypePrefix prefix;
  Name typeName;
  /// Array sizes: the declarator's, then the type's (`Real[3] x[2]` is 2x3).
  std::vector<ExprPtr> dims;
  ModificationPtr mod;
  ExprPtr condition; // `if cond`: a conditional component
  std::string conditionText; // `cond` as written
  std::string description;
  bool isProtected = false;
  bool isFinal = false;
  bool isInner = false; // `inner`: what `outer` declarations below refer to
  bool isOuter = false; // `outer`: the nearest enclosing `inner` of its name
  bool isRedeclare = false;
};

struct Extends {
  Name base;
  ModificationPtr mod;
  SourceLoc loc;
};

/// `import A.B;` (name B), `import X = A.B;`, `import A.*;`, `import A.{B, C};`
struct Import {
  std::vector<std::string> path;
  std::string alias;
  bool wildcard = false;
  std::vector<std::string> names;
  SourceLoc loc;
};

enum class EquationKind { Simple, If, For, Connect, When, Call };

struct Equation {
  EquationKind kind = EquationKind::Simple;
  SourceLoc loc;
  uint32_t length = 1;
  std::string text; // as written, whitespace collapsed
  ExprPtr lhs, rhs; // Simple; Connect (two Refs); Call (lhs is the Call)
  /// If/When: conditions; branches[k] belongs to conds[k], a last extra
  /// branch is the else. For: branches[0] is the body.
  std::vector<ExprPtr> conds;
  std::vector<std::vector<Equation>> branches;
  std::vector<ForIndex> iterators; // For
};

enum class StatementKind {
  Assign, TupleAssign, Call, If, For, While, When, Break, Return
};

struct Statement {
  StatementKind kind = StatementKind::Assign;
  SourceLoc loc;
  uint32_t length = 1;
  ExprPtr lhs, rhs;             // Assign: lhs Ref := rhs; Call: rhs is the Call
  std::vector<ExprPtr> targets; // TupleAssign: (targets) := rhs
  std::vector<ExprPtr> conds;
  std::vector<std::vector<Statement>> branches;
  std::vector<ForIndex> iterators;
};

enum class ClassKind {
  Class, Model, Record, Block, Connector, Type, Package, Function, Operator
};
const char *classKindName(ClassKind k);

struct ClassDef {
  std::string name;
  ClassKind kind = ClassKind::Model;
  bool partial = false;
  /// `impure function`: calls may differ with the same arguments.
  bool impure = false;
  bool encapsulated = false;
  bool expandable = false;
  SourceLoc loc;
  uint32_t length = 1;
  std::string description;
  ClassDef *parent = nullptr; // enclosing class; null at file top level
  uint32_t file = 0;

  // Long form.
  std::vector<Component> components;
  std::vector<Extends> extends;
  std::vector<Import> imports;
  std::vector<std::unique_ptr<ClassDef>> classes;
  std::vector<Equation> equations;
  std::vector<Equation> initialEquations;
  std::vector<Statement> algorithm; // function bodies
  /// The algorithm sections of a model, block, ... each on its own.
  std::vector<std::vector<Statement>> modelAlgorithms;
  /// Its `initial algorithm` sections.
  std::vector<std::vector<Statement>> initialAlgorithms;
  bool isExternal = false;
  /// The `external` clause of a function (MLS 12.9): language, and the call
  /// as written; `function` empty when no call is written (the default
  /// mapping: the function's own name, inputs in order, the output returned).
  struct ExternalClause {
    std::string language = "C";
    SourceLoc loc;
    uint32_t length = 1;
    ExprPtr output; // `y = f(...)`: the component reference y, else null
    std::string function;
    std::vector<ExprPtr> args;
  } external;
  std::vector<ModificationPtr> annotations; // class annotations

  // Short form: `type V = input Real[3](unit = "V");`
  bool isShort = false;
  TypePrefix shortPrefix;
  Name shortBase;
  std::vector<ExprPtr> shortDims;
  ModificationPtr shortMod;

  bool isEnumeration = false;
  std::vector<std::string> enumLiterals;

  /// The class path from the file's top: `Electrical.Resistor`.
  std::string qualifiedName() const;
};

/// One parsed file.
struct StoredDefinition {
  uint32_t file = 0;
  std::vector<std::unique_ptr<ClassDef>> classes;
  /// `within A.B;` (MLS 13.2.2.2): the package the file's classes belong
  /// to (no parts: `within;`, the top level).
  bool hasWithin = false;
  Name within;
};

} // namespace ldae::frontend::ast
