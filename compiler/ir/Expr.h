// The expression DAG every stage of ldaec works on. Nodes are immutable and
// hash-consed by their ExprContext: two structurally equal expressions are
// the same node, so equality is a pointer compare and common subexpressions
// are shared. Nodes are ordered by creation id (never by pointer) wherever an
// order is needed, so results are deterministic.
#pragma once

#include <cstdint>
#include <span>

namespace ldae::ir {

using VarId = uint32_t;
using ParamId = uint32_t;

enum class ExprKind : uint8_t {
  Constant,  // a double
  Parameter, // a parameter of the model, by ParamId
  Variable,  // variable VarId with derivative order k: x, der(x), der(x,2)...
  Time,      // the independent variable
  Pre,       // pre(v): the value of variable v just before an event
  Add,       // n-ary sum, canonical operand order
  Mul,       // n-ary product, canonical operand order (a constant first)
  Pow,       // base ^ exponent; division is a * b^-1
  Call,      // a built-in function, see FuncKind
  If,        // if operand0 then operand1 else operand2
  Compare,   // operand0 <cmp> operand1, value 1 or 0; noEvent() when
             // written inside noEvent (no event, evaluated directly)
  And,       // n-ary logical and, value 1 or 0
  Or,        // n-ary logical or, value 1 or 0
  Not,       // logical not, value 1 or 0
  External,  // output k of external function `index` (ir/External.h) at the
             // operands; an impure call carries a serial in its value so
             // that two calls are never one node
};

/// Built-in functions of LANGUAGE.md.
enum class FuncKind : uint8_t {
  Sin, Cos, Tan, Asin, Acos, Atan, Atan2, Sinh, Cosh, Tanh,
  Exp, Log, Log10, Sqrt, Abs, Sign, Min, Max, Floor, Ceil, Mod,
};
/// Number of arguments `f` takes (1 or 2).
unsigned funcArity(FuncKind f);
/// The name as written in lsd: "sin", "atan2"...
const char *funcName(FuncKind f);

enum class CompareKind : uint8_t { Lt, Le, Gt, Ge, Eq, Ne };
const char *compareSymbol(CompareKind c); // "<", "<=", ... "==", "<>"

class Expr;
using ExprRef = const Expr *;

/// A variable with a derivative order: the key of incidence and
/// differentiation queries (`x` is {x, 0}, `der(x)` is {x, 1}).
struct VarKey {
  VarId var = 0;
  unsigned order = 0;
  friend bool operator==(const VarKey &, const VarKey &) = default;
  friend auto operator<=>(const VarKey &, const VarKey &) = default;
};

class Expr {
public:
  ExprKind kind() const { return kind_; }
  /// Creation order within the context: stable, deterministic ordering key.
  uint32_t id() const { return id_; }
  size_t hash() const { return hash_; }

  double constant() const { return value_; }           // Constant
  ParamId param() const { return index_; }              // Parameter
  VarId var() const { return index_; }                  // Variable, Pre
  unsigned order() const { return order_; }             // Variable
  VarKey varKey() const { return {index_, order_}; }    // Variable
  uint32_t externalId() const { return index_; }      // External
  unsigned externalOutput() const { return order_; }  // External
  FuncKind func() const { return static_cast<FuncKind>(sub_); }
  CompareKind compare() const {
    return static_cast<CompareKind>(sub_ & ~kNoEventBit);
  }
  /// Compare: written inside noEvent(), so it generates no event and is
  /// evaluated directly (a different node from the same relation outside).
  bool noEvent() const { return (sub_ & kNoEventBit) != 0; }
  static constexpr uint8_t kNoEventBit = 0x80;

  std::span<const ExprRef> operands() const { return {ops_, numOps_}; }
  ExprRef operand(unsigned i) const { return ops_[i]; }
  unsigned numOperands() const { return numOps_; }

  bool isConstant() const { return kind_ == ExprKind::Constant; }
  bool isConstant(double v) const { return isConstant() && value_ == v; }
  /// True for Compare, And, Or, Not: expressions whose value is 0 or 1.
  bool isBoolean() const;

private:
  friend class ExprContext;
  Expr() = default;

  ExprKind kind_ = ExprKind::Constant;
  uint8_t sub_ = 0; // FuncKind or CompareKind
  uint16_t order_ = 0;
  uint32_t index_ = 0;
  uint32_t id_ = 0;
  uint32_t numOps_ = 0;
  double value_ = 0;
  size_t hash_ = 0;
  const ExprRef *ops_ = nullptr; // owned by the context's arena
  // Bookkeeping of the owning context, not part of the value: the uniquing
  // list of nodes with this one as pivot (see ExprContext::intern) and
  // whether the node is total (ExprContext::isTotal).
  mutable const Expr *firstUser_ = nullptr;
  mutable const Expr *nextUser_ = nullptr;
  mutable uint8_t userCount_ = 0;
  bool total_ = false;
};

/// Orders expressions by creation id: use for every sorted container.
struct ExprIdLess {
  bool operator()(ExprRef a, ExprRef b) const { return a->id() < b->id(); }
};

} // namespace ldae::ir
