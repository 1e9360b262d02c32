// Lowering a DaeSystem into the code plan: maps variables to y/y' slots by
// the layout rule, differentiates residuals for the Jacobians (structural
// sparsity: only symbolically nonzero entries), rewrites the IR's canonical
// forms back into cheap operations (a + (-1)*b -> a - b, a * b^-1 -> a / b,
// x^3 -> multiplications), drops dead nodes and cuts functions into chunks.
#include "codegen/PlanLowering.h"

#include "codegen/EventPlan.h"
#include "codegen/LoopRolling.h"

#include "ir/Differentiate.h"
#include "ir/External.h"
#include "ir/Query.h"
#include "ir/Substitute.h"
#include "ldae/model.h"
#include "support/SourceManager.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>

namespace ldae::codegen {

using ir::ExprKind;
using ir::ExprRef;
using ir::FuncKind;
using ir::VarKey;

namespace {

/// Where a variable key lives: y[index] or yp[index].
struct Slot {
  uint32_t index;
  bool derivative;
};
struct VarKeyHash {
  size_t operator()(VarKey k) const {
    return std::hash<uint64_t>()(uint64_t(k.var) << 8 ^ k.order);
  }
};
using KeyMap = std::unordered_map<VarKey, Slot, VarKeyHash>;

/// The layout rule: slot i's key reads y[i]; the next order of a
/// differential unknown reads yp[i] (a slot's own key wins a clash).
/// `slotKeys` overrides unknowns[i].key when not empty.
KeyMap buildKeyMap(const ir::DaeSystem &sys, const std::vector<bool> &diff,
                   const std::vector<VarKey> &slotKeys = {}) {
  KeyMap m;
  m.reserve(2 * sys.unknowns.size());
  ir::forEachLayoutRead(sys, slotKeys, diff,
                        [&](VarKey k, uint32_t slot, bool derivative) {
                          m.emplace(k, Slot{slot, derivative});
                        });
  return m;
}

std::string keyName(const ir::DaeSystem &sys, VarKey k) {
  if (sys.model && k.var < sys.model->variables.size())
    return sys.model->variableName(k);
  std::string s = "v" + std::to_string(k.var);
  return k.order ? "der(" + s + (k.order > 1 ? ", " + std::to_string(k.order) : "") + ")" : s;
}

bool isIntegral(double v) { return std::floor(v) == v && std::fabs(v) < 1e9; }

/// Builds one plan function from IR roots.
class FunctionBuilder {
public:
  FunctionBuilder(PlanFunction &fn, const KeyMap &keys,
                  const ir::DaeSystem &sys, unsigned nParams)
      : fn_(fn), keys_(keys), sys_(sys), nParams_(nParams) {}

  /// Lowers `e`; on failure records an error and returns node 0.
  uint32_t lower(ExprRef e) {
    if (auto it = memo_.find(key(e)); it != memo_.end())
      return it->second;
    // Lower operands first (post-order, not descending into what is already
    // lowered), so the recursion in lowerNode stays shallow however deep
    // the expression is, and each call costs only its new nodes. lowerNode
    // may call back here (for operands of operands): those calls get a
    // stack of their own.
    std::vector<std::pair<ExprRef, unsigned>> local;
    auto &stack = depth_++ == 0 ? stack_ : local;
    stack.assign(1, {e, 0});
    while (!stack.empty()) {
      auto &[x, next] = stack.back();
      if (next == 0 && guardsBranches(x)) {
        ExprRef done = x;
        stack.pop_back();
        uint32_t k = lowerGuardedIf(done);
        memo_.emplace(key(done), k);
        continue;
      }
      if (next < x->numOperands()) {
        ExprRef operand = x->operand(next++);
        if (!memo_.count(key(operand)))
          stack.push_back({operand, 0});
        continue;
      }
      ExprRef done = x;
      stack.pop_back();
      if (!memo_.count(key(done))) {
        uint32_t k = lowerNode(done);
        memo_.emplace(key(done), k);
      }
    }
    --depth_;
    return memo_.at(key(e));
  }

  uint32_t emit(PlanNode n) {
    auto flag = [&](uint32_t i) { return fn_.nodes[i].mayFail; };
    switch (n.op) {
    case OpCode::Div:
      n.checks = !(fn_.nodes[n.b].op == OpCode::Const && fn_.nodes[n.b].value != 0);
      break;
    case OpCode::Pow:
      n.checks = true;
      break;
    case OpCode::Sqrt:
      n.checks = !(fn_.nodes[n.a].op == OpCode::Const && fn_.nodes[n.a].value >= 0);
      break;
    case OpCode::Func1: {
      auto f = FuncKind(n.sub);
      n.checks = f == FuncKind::Log || f == FuncKind::Log10 ||
                 f == FuncKind::Asin || f == FuncKind::Acos;
      break;
    }
    case OpCode::Func2:
      n.checks = FuncKind(n.sub) == FuncKind::Mod;
      break;
    case OpCode::ExtCall:
      // C code says it failed by a NaN (a compiled function's assertion or
      // subscript out of range, CompiledFunctions.cpp): a domain error, as
      // sqrt of a negative number is, never a silent NaN in a row.
      n.checks = true;
      break;
    default:
      break;
    }
    n.mayFail = n.checks;
    for (unsigned i = 0; i < numOperands(n.op); ++i)
      n.mayFail |= flag(n.operand(i));
    fn_.nodes.push_back(n);
    return fn_.nodes.size() - 1;
  }
  uint32_t leaf(OpCode op, int32_t index = 0, double value = 0) {
    PlanNode n;
    n.op = op;
    n.index = index;
    n.value = value;
    return emit(n);
  }
  uint32_t constant(double v) {
    auto [it, fresh] = consts_.emplace(v, 0);
    if (fresh)
      it->second = leaf(OpCode::Const, 0, v);
    return it->second;
  }
  uint32_t cj() {
    if (cj_ < 0)
      cj_ = leaf(OpCode::Cj);
    return cj_;
  }
  uint32_t op(OpCode o, uint32_t a, uint32_t b = 0, uint32_t c = 0,
              uint8_t sub = 0) {
    PlanNode n;
    n.op = o;
    n.a = a;
    n.b = b;
    n.c = c;
    n.sub = sub;
    return emit(n);
  }
  void store(uint32_t node, uint8_t array, uint32_t index, uint32_t row) {
    fn_.stores.push_back({node, array, index, row});
  }
  const std::string &error() const { return error_; }

private:
  uint32_t node(ExprRef e) { return lower(e); }

  static constexpr uint32_t kAlways = UINT32_MAX;
  using MemoKey = std::pair<ExprRef, uint32_t>;
  struct MemoHash {
    size_t operator()(const MemoKey &k) const {
      return std::hash<ExprRef>()(k.first) * 31 + k.second;
    }
  };
  /// An expression with an external call is lowered once per guard it is
  /// needed under; every other expression once.
  MemoKey key(ExprRef e) {
    return {e, guard_ != kAlways && callsExternal(e) ? guard_ : kAlways};
  }

  bool callsExternal(ExprRef e) {
    if (auto it = callsExternal_.find(e); it != callsExternal_.end())
      return it->second;
    // Post-order, not descending into what is already known.
    std::vector<std::pair<ExprRef, unsigned>> stack{{e, 0}};
    while (!stack.empty()) {
      auto &[x, next] = stack.back();
      if (next < x->numOperands()) {
        ExprRef operand = x->operand(next++);
        if (!callsExternal_.count(operand))
          stack.push_back({operand, 0});
        continue;
      }
      bool c = x->kind() == ExprKind::External;
      for (ExprRef o : x->operands())
        c = c || callsExternal_.at(o);
      callsExternal_.emplace(x, c);
      stack.pop_back();
    }
    return callsExternal_.at(e);
  }

  /// An if-expression with an external call in a branch: the call is made
  /// only where its branch is taken. MSL's tables keep state between
  /// calls (CombiTimeTable's next time event advances one interval per
  /// call), so a when-equation's `getNextTimeEvent(...)` evaluated at an
  /// event of another clause, as a select evaluates both sides, moved
  /// BooleanTable's events past the end of its table.
  bool guardsBranches(ExprRef e) {
    return e->kind() == ExprKind::If && anyExternal_ &&
           (callsExternal(e->operand(1)) || callsExternal(e->operand(2)));
  }

  uint32_t lowerGuardedIf(ExprRef e) {
    uint32_t cond = lower(e->operand(0));
    uint32_t outer = guard_;
    uint32_t taken = op(OpCode::Compare, cond, constant(0), 0,
                        uint8_t(ir::CompareKind::Ne));
    uint32_t notTaken = op(OpCode::Not, cond);
    guard_ = outer == kAlways ? taken : op(OpCode::And, outer, taken);
    uint32_t then = lower(e->operand(1));
    guard_ = outer == kAlways ? notTaken : op(OpCode::And, outer, notTaken);
    uint32_t otherwise = lower(e->operand(2));
    guard_ = outer;
    return op(OpCode::Select, cond, then, otherwise);
  }

  uint32_t lowerNode(ExprRef e) {
    switch (e->kind()) {
    case ExprKind::Constant:
      return constant(e->constant());
    case ExprKind::Parameter:
      if (e->param() >= nParams_)
        fail("parameter index " + std::to_string(e->param()) +
             " is out of range");
      return leaf(OpCode::LoadP, e->param());
    case ExprKind::Variable:
      return variable(e->varKey());
    case ExprKind::Pre: // the value before an event: the current value here
      return variable(VarKey{e->var(), 0});
    case ExprKind::Time:
      return leaf(OpCode::Time);
    case ExprKind::Add:
      return lowerSum(e);
    case ExprKind::Mul:
      return lowerProduct(e->operands());
    case ExprKind::Pow:
      return lowerPow(e);
    case ExprKind::Call: {
      FuncKind f = e->func();
      if (f == FuncKind::Sqrt)
        return op(OpCode::Sqrt, node(e->operand(0)));
      if (ir::funcArity(f) == 1)
        return op(OpCode::Func1, node(e->operand(0)), 0, 0, uint8_t(f));
      return op(OpCode::Func2, node(e->operand(0)), node(e->operand(1)), 0,
                uint8_t(f));
    }
    case ExprKind::If:
      return op(OpCode::Select, node(e->operand(0)), node(e->operand(1)),
                node(e->operand(2)));
    case ExprKind::Compare:
      return op(OpCode::Compare, node(e->operand(0)), node(e->operand(1)), 0,
                uint8_t(e->compare()));
    case ExprKind::And:
    case ExprKind::Or: {
      OpCode o = e->kind() == ExprKind::And ? OpCode::And : OpCode::Or;
      uint32_t acc = node(e->operand(0));
      if (e->numOperands() == 1)
        return op(OpCode::Compare, acc, constant(0), 0,
                  uint8_t(ir::CompareKind::Ne));
      for (unsigned i = 1; i < e->numOperands(); ++i)
        acc = op(o, acc, node(e->operand(i)));
      return acc;
    }
    case ExprKind::Not:
      return op(OpCode::Not, node(e->operand(0)));
    case ExprKind::External: {
      // Arguments as a chain of ExtArg nodes (an operation reads at most
      // three operands); index is the ir id until lowerToPlan renumbers it.
      uint32_t last = 0;
      for (unsigned i = 0; i < e->numOperands(); ++i) {
        uint32_t v = node(e->operand(i));
        uint32_t k = op(OpCode::ExtArg, v, i == 0 ? v : last);
        fn_.nodes[k].index = int32_t(i);
        last = k;
      }
      uint32_t args = e->numOperands() ? last : constant(0);
      uint32_t call = op(OpCode::ExtCall, args,
                         guard_ == kAlways ? args : guard_, 0,
                         guard_ == kAlways ? 0 : 1);
      fn_.nodes[call].index = int32_t(e->externalId());
      fn_.nodes[call].value = e->externalOutput();
      return call;
    }
    }
    fail("unknown expression kind");
    return constant(0);
  }

  uint32_t variable(VarKey k) {
    auto it = keys_.find(k);
    if (it == keys_.end()) {
      fail("'" + keyName(sys_, k) +
           "' is neither an unknown nor the derivative of a differential "
           "unknown of the system");
      return constant(0);
    }
    return leaf(it->second.derivative ? OpCode::LoadYp : OpCode::LoadY,
                it->second.index);
  }

  /// a + (-1)*b + ... -> (a - b) + ...; terms keep their order.
  uint32_t lowerSum(ExprRef e) {
    struct Term {
      uint32_t node;
      bool negated;
    };
    std::vector<Term> terms;
    for (ExprRef t : e->operands()) {
      if (t->kind() == ExprKind::Mul && t->operand(0)->isConstant(-1.0)) {
        auto rest = t->operands().subspan(1);
        terms.push_back({rest.size() == 1 ? node(rest[0]) : lowerProduct(rest),
                         true});
      } else {
        terms.push_back({node(t), false});
      }
    }
    auto firstPos = std::find_if(terms.begin(), terms.end(),
                                 [](const Term &t) { return !t.negated; });
    uint32_t acc;
    if (firstPos == terms.end()) {
      acc = op(OpCode::Neg, terms[0].node);
      firstPos = terms.begin();
    } else {
      acc = firstPos->node;
    }
    for (auto it = terms.begin(); it != terms.end(); ++it)
      if (it != firstPos)
        acc = op(it->negated ? OpCode::Sub : OpCode::Add, acc, it->node);
    return acc;
  }

  /// c * a * b^-1 * d^-2 -> (c * a) / (b * d^2); -1 * x -> -x.
  uint32_t lowerProduct(std::span<const ExprRef> factors) {
    double c = 1;
    std::vector<uint32_t> num, den;
    for (ExprRef f : factors) {
      if (f->isConstant()) {
        c *= f->constant();
        continue;
      }
      if (f->kind() == ExprKind::Pow && f->operand(1)->isConstant()) {
        double k = f->operand(1)->constant();
        if (k < 0 && (isIntegral(k) || k == -0.5)) {
          den.push_back(positivePower(node(f->operand(0)), -k));
          continue;
        }
      }
      num.push_back(node(f));
    }
    bool negate = c == -1 && !num.empty();
    if (!negate && (c != 1 || num.empty()))
      num.insert(num.begin(), constant(c));
    uint32_t acc = num[0];
    for (size_t i = 1; i < num.size(); ++i)
      acc = op(OpCode::Mul, acc, num[i]);
    if (!den.empty()) {
      uint32_t d = den[0];
      for (size_t i = 1; i < den.size(); ++i)
        d = op(OpCode::Mul, d, den[i]);
      acc = op(OpCode::Div, acc, d);
    }
    if (negate)
      acc = op(OpCode::Neg, acc);
    return acc;
  }

  /// base^k for k a positive integer or 0.5.
  uint32_t positivePower(uint32_t base, double k) {
    if (k == 0.5)
      return op(OpCode::Sqrt, base);
    if (k == 1)
      return base;
    if (k <= 64) {
      uint32_t n = op(OpCode::PowInt, base);
      fn_.nodes[n].index = int32_t(k);
      return n;
    }
    return op(OpCode::Pow, base, constant(k));
  }

  uint32_t lowerPow(ExprRef e) {
    uint32_t base = node(e->operand(0));
    ExprRef ex = e->operand(1);
    if (ex->isConstant()) {
      double k = ex->constant();
      if (k > 0 && (isIntegral(k) || k == 0.5))
        return positivePower(base, k);
      if (k < 0 && (isIntegral(k) || k == -0.5))
        return op(OpCode::Div, constant(1), positivePower(base, -k));
    }
    return op(OpCode::Pow, base, node(ex));
  }

  void fail(std::string msg) {
    if (error_.empty())
      error_ = std::move(msg);
  }

  PlanFunction &fn_;
  const KeyMap &keys_;
  const ir::DaeSystem &sys_;
  unsigned nParams_;
  std::unordered_map<MemoKey, uint32_t, MemoHash> memo_;
  std::unordered_map<ExprRef, bool> callsExternal_;
  /// No model without external functions pays for the analysis.
  bool anyExternal_ = ir::anyExternal();
  /// The node that must be nonzero for the external calls being lowered
  /// to be made (kAlways: unconditionally).
  uint32_t guard_ = kAlways;
  std::vector<std::pair<ExprRef, unsigned>> stack_;
  unsigned depth_ = 0;
  std::map<double, uint32_t> consts_;
  int64_t cj_ = -1;
  std::string error_;
};

} // namespace

namespace {

/// Cuts `fn` into chunks of at most `size` non-leaf nodes; values a later
/// chunk reads get scratch slots.
void assignChunks(PlanFunction &fn, unsigned size) {
  size = std::max(1u, size);
  std::vector<uint32_t> chunkOf(fn.nodes.size());
  uint32_t nonLeaf = 0;
  for (size_t k = 0; k < fn.nodes.size(); ++k) {
    chunkOf[k] = nonLeaf / size;
    if (!isLeaf(fn.nodes[k].op))
      ++nonLeaf;
  }
  uint32_t numChunks = std::max<uint32_t>(1, (nonLeaf + size - 1) / size);
  fn.chunks.assign(numChunks, PlanChunk{});
  // Node ranges.
  for (uint32_t c = 0; c < numChunks; ++c) {
    fn.chunks[c].nodeBegin = c == 0 ? 0 : fn.chunks[c - 1].nodeEnd;
    uint32_t end = fn.chunks[c].nodeBegin;
    while (end < fn.nodes.size() && (chunkOf[end] == c || c + 1 == numChunks))
      ++end;
    fn.chunks[c].nodeEnd = end;
  }
  // Stores run in order, each in the chunk where its value is ready.
  std::vector<uint32_t> storeChunk(fn.stores.size());
  uint32_t pos = 0;
  for (size_t i = 0; i < fn.stores.size(); ++i) {
    pos = std::max(pos, fn.stores[i].node);
    fn.stores[i].after = pos;
    storeChunk[i] = std::min(chunkOf.empty() ? 0 : chunkOf[pos], numChunks - 1);
  }
  for (uint32_t c = 0, i = 0; c < numChunks; ++c) {
    fn.chunks[c].storeBegin = i;
    while (i < fn.stores.size() && storeChunk[i] == c)
      ++i;
    fn.chunks[c].storeEnd = i;
  }
  // Spill slots for values crossing a chunk boundary.
  fn.spill.assign(fn.nodes.size(), -1);
  fn.numSpillSlots = 0;
  auto use = [&](uint32_t operand, uint32_t userChunk) {
    if (isLeaf(fn.nodes[operand].op) || chunkOf[operand] == userChunk ||
        fn.spill[operand] >= 0)
      return;
    fn.spill[operand] = fn.numSpillSlots;
    fn.numSpillSlots += fn.nodes[operand].mayFail ? 2 : 1;
  };
  if (numChunks > 1) {
    // An external call reads its whole argument chain.
    for (uint32_t k = 0; k < fn.nodes.size(); ++k)
      if (fn.nodes[k].op == OpCode::ExtCall)
        for (uint32_t arg : externalArguments(fn.nodes, k))
          use(arg, chunkOf[k]);
    for (size_t k = 0; k < fn.nodes.size(); ++k)
      for (unsigned i = 0; i < numOperands(fn.nodes[k].op); ++i)
        use(fn.nodes[k].operand(i), chunkOf[k]);
    for (size_t i = 0; i < fn.stores.size(); ++i)
      use(fn.stores[i].node, storeChunk[i]);
  }
}

struct JacEntry {
  uint32_t col, row;
  ExprRef dy, dyp;
};

/// Nonzero entries of dF/dy and dF/dy' (merged per (col,row)), CSC order.
std::vector<JacEntry> jacobianEntries(const ir::DaeSystem &sys,
                                      std::span<const ExprRef> rows,
                                      const KeyMap &keys,
                                      ir::Differentiator &diff) {
  // The terms of each row that contain each key: a long sum (the ground
  // node's current balance has a term per branch) is then differentiated
  // term by term, not re-walked whole for every variable, which keeps the
  // Jacobian linear in the model size. Keys are grouped per row by sorting
  // the row's (key, term) pairs: no model-wide map.
  std::vector<JacEntry> entries;
  std::vector<std::pair<VarKey, ExprRef>> keyTerms;
  std::vector<ExprRef> parts, others;
  auto readsKey = [&](ExprRef e) {
    for (VarKey k : ir::freeVariables(e))
      if (keys.count(k))
        return true;
    return false;
  };
  for (uint32_t r = 0; r < rows.size(); ++r) {
    std::span<const ExprRef> terms(&rows[r], 1);
    // The same for a sum times factors free of the keys: a computed
    // variable's value -rest / coefficient (the ground's current of an RC
    // ladder: N terms) would otherwise be walked whole for each of its N
    // keys, quadratic (codegen 16 s at N = 3000).
    ExprRef scale = nullptr;
    if (rows[r]->kind() == ir::ExprKind::Add) {
      terms = rows[r]->operands();
    } else if (rows[r]->kind() == ir::ExprKind::Mul) {
      ExprRef sum = nullptr;
      bool split = true;
      others.clear();
      for (ExprRef f : rows[r]->operands()) {
        if (!readsKey(f))
          others.push_back(f);
        else if (!sum && f->kind() == ir::ExprKind::Add)
          sum = f;
        else
          split = false;
      }
      if (split && sum) {
        terms = sum->operands();
        scale = sys.ctx->mul(others);
      }
    }
    keyTerms.clear();
    for (ExprRef t : terms)
      for (VarKey k : ir::freeVariables(t))
        if (keys.count(k))
          keyTerms.push_back({k, t});
    std::stable_sort(keyTerms.begin(), keyTerms.end(),
                     [](auto &a, auto &b) { return a.first < b.first; });
    for (size_t i = 0; i < keyTerms.size();) {
      VarKey k = keyTerms[i].first;
      parts.clear();
      for (; i < keyTerms.size() && keyTerms[i].first == k; ++i)
        parts.push_back(diff.partial(keyTerms[i].second, k));
      ExprRef d = sys.ctx->add(parts);
      if (scale)
        d = sys.ctx->mul(scale, d);
      if (d->isConstant(0.0))
        continue;
      Slot s = keys.at(k);
      entries.push_back({s.index, r, s.derivative ? nullptr : d,
                         s.derivative ? d : nullptr});
    }
  }
  std::sort(entries.begin(), entries.end(), [](auto &a, auto &b) {
    return std::tie(a.col, a.row) < std::tie(b.col, b.row);
  });
  std::vector<JacEntry> merged;
  for (const JacEntry &e : entries) {
    if (!merged.empty() && merged.back().col == e.col &&
        merged.back().row == e.row) {
      if (e.dy)
        merged.back().dy = e.dy;
      if (e.dyp)
        merged.back().dyp = e.dyp;
    } else {
      merged.push_back(e);
    }
  }
  return merged;
}

/// Plan node of dy + cj * dyp (either part may be absent).
uint32_t jacobianValue(FunctionBuilder &b, const JacEntry &e) {
  uint32_t part = 0;
  bool hasYp = false;
  if (e.dyp) {
    hasYp = true;
    part = e.dyp->isConstant(1.0) ? b.cj() : b.op(OpCode::Mul, b.cj(), b.lower(e.dyp));
  }
  if (!e.dy)
    return part;
  uint32_t dy = b.lower(e.dy);
  return hasYp ? b.op(OpCode::Add, dy, part) : dy;
}

std::string cIdentifier(const std::string &s) {
  std::string out;
  for (char ch : s)
    out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0])))
    out = "m_" + out;
  return out;
}

} // namespace

/// Fills the binding tables of `plan` (see CodePlan::bind) and returns the
/// expressions of the bind function in their output order.
static std::vector<ExprRef> planBindings(const ir::DaeSystem &sys,
                                         CodePlan &plan) {
  std::vector<ExprRef> values;
  const unsigned np = plan.paramValues.size();
  plan.structuralParams.assign(np, 0);
  if (!sys.model)
    return values;
  const std::vector<ir::Parameter> &params = sys.model->parameters;
  auto binding = [&](unsigned p) {
    return p < params.size() ? params[p].binding : nullptr;
  };
  // 1: fixes the structure (Model::structuralParameters); 2: a constant.
  const std::vector<bool> structural = sys.model->structuralParameters();
  for (unsigned p = 0; p < np && p < params.size(); ++p)
    plan.structuralParams[p] = params[p].isConstant ? 2 : structural[p] ? 1 : 0;
  // Depth of each binding chain: a pass of the bind function settles one
  // level. Bindings form no cycle (the frontend rejects those).
  std::vector<int> depth(np, -1);
  auto depthOf = [&](auto &self, unsigned p) -> int {
    if (depth[p] >= 0)
      return depth[p];
    int d = 0;
    if (ExprRef b = binding(p)) {
      depth[p] = 0; // guards a cycle the frontend missed
      for (ir::ParamId q : ir::freeParameters(b))
        if (q < np)
          d = std::max(d, self(self, q) + 1);
    }
    return depth[p] = d;
  };
  for (unsigned p = 0; p < np; ++p)
    if (ExprRef b = binding(p); b && !plan.structuralParams[p]) {
      plan.boundParams.push_back(p);
      plan.bindPasses =
          std::max<unsigned>(plan.bindPasses, depthOf(depthOf, p));
      values.push_back(b);
    }
  for (unsigned i = 0; i < sys.unknowns.size(); ++i)
    if (ExprRef b = sys.unknowns[i].startBinding) {
      plan.boundStarts.push_back(i);
      values.push_back(b);
    }
  // The program evaluates bindings over its parameters alone, before the
  // initial event, where every discrete value (and its pre()) is its start.
  const std::vector<double> &start = plan.events.discreteStart;
  if (!start.empty()) {
    ir::Substitution atStart(*sys.ctx);
    for (unsigned k = 0; k < start.size(); ++k) {
      ExprRef value = sys.ctx->constant(start[k]);
      atStart.set(sys.ctx->param(np + k), value);
      atStart.set(sys.ctx->param(np + start.size() + k), value);
    }
    for (ExprRef &v : values)
      v = atStart.apply(v);
  }
  return values;
}

/// The constructor calls of the model's external objects (see
/// CodePlan::objects) in order of their parameters, filling objectParams.
static std::vector<ExprRef> planObjects(const ir::DaeSystem &sys,
                                        CodePlan &plan) {
  std::vector<ExprRef> calls;
  if (!sys.model)
    return calls;
  const std::vector<ir::Parameter> &params = sys.model->parameters;
  for (unsigned p = 0; p < params.size() && p < plan.paramValues.size(); ++p) {
    if (!params[p].externalObject)
      continue;
    ExprRef b = params[p].binding;
    if (!ir::isConstructorCall(b)) {
      if (plan.unmadeObject.empty())
        plan.unmadeObject = params[p].name;
      continue;
    }
    plan.objectParams.push_back(p);
    calls.push_back(b);
  }
  return calls;
}

/// The CSC pattern (n columns) of entries in CSC order.
void cscPattern(const std::vector<JacEntry> &entries, unsigned n,
                std::vector<int> &colptr, std::vector<int> &rowind) {
  colptr.assign(n + 1, 0);
  rowind.clear();
  for (const JacEntry &e : entries) {
    ++colptr[e.col + 1];
    rowind.push_back(e.row);
  }
  for (unsigned j = 0; j < n; ++j)
    colptr[j + 1] += colptr[j];
}

/// The geometric slots of a linearly implicit system (`--method sga|ode`):
/// n_ode, the projection flag, the constraints and their dense Jacobian
/// dc/dy (column-major, one row per constraint), read through a layout
/// without derivatives, so a constraint that reads y' fails to lower.
template <typename AddFunction>
static void planGeometricSlots(const ir::DaeSystem &sys, CodePlan &plan,
                               ir::Differentiator &diff,
                               AddFunction &addFunction) {
  const unsigned n = sys.unknowns.size();
  plan.nOde = n;
  plan.explicitOde = false;
  plan.projectConstraints = sys.projectOntoConstraints;
  if (sys.constraints.empty())
    return;
  KeyMap stateKeys = buildKeyMap(sys, std::vector<bool>(n, false));
  const std::vector<ExprRef> &c = sys.constraints;
  const unsigned m = c.size();
  plan.nConstraints = m;
  plan.constraints = addFunction(
      "constraints", FnSig::State, stateKeys,
      [&](FunctionBuilder &b, PlanFunction &) {
        for (uint32_t i = 0; i < m; ++i)
          b.store(b.lower(c[i]), 0, i, i);
      });
  std::vector<JacEntry> entries = jacobianEntries(sys, c, stateKeys, diff);
  plan.constraintJacobian = addFunction(
      "constraint_jacobian", FnSig::State, stateKeys,
      [&](FunctionBuilder &b, PlanFunction &fn) {
        fn.zeroFill[0] = m * n;
        for (const JacEntry &e : entries)
          b.store(b.lower(e.dy), 0, e.col * m + e.row, e.row);
      });
}

namespace {

/// Replaces the ir ids of ExtCall nodes by indices into plan.externals,
/// listing each called function once, in order of first call.
void numberExternals(CodePlan &plan) {
  std::map<int32_t, int32_t> index;
  for (PlanFunction &fn : plan.functions)
    for (PlanNode &n : fn.nodes) {
      if (n.op != OpCode::ExtCall)
        continue;
      auto [it, fresh] = index.emplace(n.index, int32_t(plan.externals.size()));
      if (fresh) {
        const ir::ExternalFunction &f = ir::externalFunction(uint32_t(n.index));
        plan.externals.push_back(
            {f.symbol, f.name, f.numInputs, f.numOutputs,
             reinterpret_cast<uintptr_t>(f.entry), f.objects});
      }
      n.index = it->second;
    }
  if (!plan.externals.empty())
    for (PlanFunction &fn : plan.functions)
      fn.externals = plan.externals;
}

} // namespace

Expected<CodePlan> lowerToPlan(const ir::DaeSystem &sys,
                               const PlanOptions &opts) {
  const unsigned n = sys.unknowns.size();
  if (sys.stateSets.empty())
    return Error{"the system has no state set"};
  for (size_t s = 0; s < sys.stateSets.size(); ++s) {
    const ir::StateSet &set = sys.stateSets[s];
    if (set.residuals.size() != n)
      return Error{"state set " + std::to_string(s) + " has " +
                   std::to_string(set.residuals.size()) + " residuals for " +
                   std::to_string(n) + " unknowns"};
    if (!set.differential.empty() && set.differential.size() != n)
      return Error{"state set " + std::to_string(s) +
                   " has a wrong number of differential flags"};
    if (!set.keys.empty() && set.keys.size() != n)
      return Error{"state set " + std::to_string(s) +
                   " has a wrong number of slot keys"};
    if (set.pivot.size() != size_t(set.pivotSize) * set.pivotSize)
      return Error{"state set " + std::to_string(s) +
                   " has a pivot matrix of the wrong size"};
  }

  CodePlan plan;
  plan.name = sys.model && !sys.model->name.empty() ? sys.model->name : "model";
  plan.symbolName = cIdentifier(plan.name);
  plan.n = n;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  plan.startTime = plan.stopTime = plan.tolerance = plan.interval = nan;
  if (sys.model) {
    const ir::Experiment &x = sys.model->experiment;
    plan.startTime = x.startTime.value_or(nan);
    plan.stopTime = x.stopTime.value_or(nan);
    plan.tolerance = x.tolerance.value_or(nan);
    plan.interval = x.interval.value_or(nan);
  }
  for (const ir::SystemUnknown &u : sys.unknowns) {
    plan.varNames.push_back(u.name);
    plan.startY.push_back(u.start);
    plan.startYp.push_back(u.startDerivative);
    plan.nominal.push_back(u.nominal > 0 ? u.nominal : 1.0);
    plan.fixed.push_back(u.fixed);
  }
  plan.paramValues = sys.parameterValues;
  plan.paramNames = sys.parameterNames;
  plan.selectionCount = sys.selectionCount;
  plan.paramNames.resize(plan.paramValues.size());
  for (size_t i = 0; i < plan.paramNames.size(); ++i)
    if (plan.paramNames[i].empty())
      plan.paramNames[i] = sys.model && i < sys.model->parameters.size()
                               ? sys.model->parameters[i].name
                               : "p" + std::to_string(i);
  auto origin = [&](const SourceLoc &loc, const char *none) {
    return sourceOrigin(opts.sources, loc, none);
  };
  if (opts.sources && !sys.residualLocs.empty()) {
    for (const SourceLoc &loc : sys.residualLocs)
      plan.residualOrigin.push_back(origin(loc, "<generated>"));
    plan.residualOrigin.resize(n, "<generated>");
  }
  if (opts.sources)
    for (const ir::SystemOutput &o : sys.outputs)
      plan.outputOrigin.push_back(origin(o.loc, ""));
  for (const ir::SystemOutput &o : sys.outputs) {
    plan.outputNames.push_back(o.name);
    plan.outputUnit.push_back(o.unit);
    plan.outputDescription.push_back(o.description);
    plan.outputAlias.push_back(o.alias);
  }
  for (size_t i = 0; i < plan.paramNames.size(); ++i) {
    bool own = sys.model && i < sys.model->parameters.size();
    plan.paramUnit.push_back(own ? sys.model->parameters[i].unit : "");
    plan.paramDescription.push_back(
        own ? sys.model->parameters[i].description : "");
  }
  plan.explicitOde = sys.form == ir::SystemForm::ExplicitOde;
  plan.algebraicErrorTest = sys.index <= 1;

  if (auto ok = planEventTables(sys, plan.events, opts.sources); !ok)
    return Error{ok.error()};
  // Discrete values and their pre() values are read past the parameters.
  const unsigned nParams = plan.pSize();
  ir::Differentiator diff(*sys.ctx);
  std::string error;

  // Adds a function built by `build` and returns its index.
  auto addFunction = [&](std::string name, FnSig sig, const KeyMap &keys,
                         auto build) {
    plan.functions.emplace_back();
    PlanFunction &fn = plan.functions.back();
    fn.name = std::move(name);
    fn.sig = sig;
    FunctionBuilder b(fn, keys, sys, nParams);
    build(b, fn);
    if (error.empty() && !b.error().empty())
      error = "in " + fn.name + ": " + b.error();
    removeDeadNodes(fn);
    if (opts.loops)
      rollLoops(fn);
    assignChunks(fn, opts.chunkSize);
    return int(plan.functions.size() - 1);
  };
  auto valuesFunction = [&](std::string name, std::span<const ExprRef> exprs,
                            const KeyMap &keys) {
    return addFunction(std::move(name), FnSig::Values, keys,
                       [&](FunctionBuilder &b, PlanFunction &) {
                         for (uint32_t i = 0; i < exprs.size(); ++i)
                           b.store(b.lower(exprs[i]), 0, i, i);
                       });
  };

  const std::vector<bool> anyDiff = ir::anyDifferential(sys);

  for (size_t s = 0; s < sys.stateSets.size(); ++s) {
    const ir::StateSet &set = sys.stateSets[s];
    const std::vector<bool> flags = ir::setDifferential(sys, s);
    KeyMap keys = buildKeyMap(sys, flags, set.keys);
    StateSetPlan sp;
    sp.isDifferential.assign(flags.begin(), flags.end());
    std::string suffix = "_" + std::to_string(s);
    sp.residual = valuesFunction("residual" + suffix, set.residuals, keys);

    std::vector<JacEntry> entries =
        jacobianEntries(sys, set.residuals, keys, diff);
    cscPattern(entries, n, sp.colptr, sp.rowind);
    sp.jacobianCsc = addFunction(
        "jac_csc" + suffix, FnSig::Jacobian, keys,
        [&](FunctionBuilder &b, PlanFunction &) {
          for (uint32_t k = 0; k < entries.size(); ++k)
            b.store(jacobianValue(b, entries[k]), 0, k, entries[k].row);
        });
    if (useDenseJacobian(n))
      sp.jacobianDense = addFunction(
          "jac_dense" + suffix, FnSig::Jacobian, keys,
          [&](FunctionBuilder &b, PlanFunction &fn) {
            fn.zeroFill[0] = n * n;
            for (const JacEntry &e : entries)
              b.store(jacobianValue(b, e), 0, e.col * n + e.row, e.row);
          });
    if (set.pivotSize > 0) {
      sp.pivotSize = set.pivotSize;
      sp.pivot = valuesFunction("pivot" + suffix, set.pivot, keys);
    }
    sp.description = "states:";
    for (size_t i = 0; i < set.states.size(); ++i)
      sp.description += (i ? ", " : " ") + set.states[i];
    plan.stateSets.push_back(std::move(sp));
  }
  {
    const ir::StateSet &set0 = sys.stateSets[0];
    KeyMap keys = buildKeyMap(sys, ir::setDifferential(sys, 0), set0.keys);
    for (size_t d = 0; d < sys.dynamicSets.size(); ++d) {
      const ir::DynamicStateSet &ds = sys.dynamicSets[d];
      DynamicSetPlan dp;
      dp.rows = ds.rows;
      dp.forced = ds.forced;
      dp.candidates = ds.candidates;
      std::string suffix = "_" + std::to_string(d);
      dp.jacobian =
          valuesFunction("dynamic_jacobian" + suffix, ds.jacobian, keys);
      dp.values = valuesFunction("dynamic_values" + suffix, ds.values, keys);
      dp.param = static_cast<int>(ds.param);
      dp.start = ds.start;
      dp.names = ds.names;
      for (ir::VarKey k : ds.states) {
        int slot = -1;
        for (unsigned i = 0; i < n && slot < 0; ++i)
          if (sys.unknowns[i].key == k)
            slot = static_cast<int>(i);
        if (slot < 0)
          return Error{"a dynamic state set's state has no slot"};
        dp.stateSlots.push_back(slot);
      }
      plan.dynamicSets.push_back(std::move(dp));
    }
  }

  KeyMap keys = buildKeyMap(sys, anyDiff);
  plan.nInit = sys.initialResiduals.size();
  plan.initResidual =
      valuesFunction("init_residual", sys.initialResiduals, keys);
  std::vector<JacEntry> initEntries =
      jacobianEntries(sys, sys.initialResiduals, keys, diff);
  // dF/dy and dF/dy' of `m` rows, both dense column-major m x n.
  auto denseParts = [&](std::string name, unsigned m,
                        const std::vector<JacEntry> &entries) {
    return addFunction(std::move(name), FnSig::InitJacobian, keys,
                       [&](FunctionBuilder &b, PlanFunction &fn) {
                         fn.zeroFill[0] = fn.zeroFill[1] = m * n;
                         for (const JacEntry &e : entries) {
                           if (e.dy)
                             b.store(b.lower(e.dy), 0, e.col * m + e.row,
                                     e.row);
                           if (e.dyp)
                             b.store(b.lower(e.dyp), 1, e.col * m + e.row,
                                     e.row);
                         }
                       });
  };
  if (useDenseJacobian(n))
    plan.initJacobian = denseParts("init_jacobian", plan.nInit, initEntries);
  // The sparse form: one pattern for both parts (an entry absent from one
  // of them is stored as 0 there by the zero fill).
  cscPattern(initEntries, n, plan.initColptr, plan.initRowind);
  plan.initJacobianCsc = addFunction(
      "init_jac_csc", FnSig::InitJacobian, keys,
      [&](FunctionBuilder &b, PlanFunction &fn) {
        fn.zeroFill[0] = fn.zeroFill[1] = initEntries.size();
        for (uint32_t k = 0; k < initEntries.size(); ++k) {
          const JacEntry &e = initEntries[k];
          if (e.dy)
            b.store(b.lower(e.dy), 0, k, e.row);
          if (e.dyp)
            b.store(b.lower(e.dyp), 1, k, e.row);
        }
      });
  if (!sys.writtenResiduals.empty()) {
    // Evaluated at events only: dense whatever the size (the jump rule's
    // Wong sequences are dense too).
    plan.nWritten = sys.writtenResiduals.size();
    plan.writtenResidual =
        valuesFunction("written_residual", sys.writtenResiduals, keys);
    plan.writtenJacobian = denseParts(
        "written_jacobian", plan.nWritten,
        jacobianEntries(sys, sys.writtenResiduals, keys, diff));
  }
  plan.nRoots = sys.roots.size();
  plan.roots = valuesFunction("roots", sys.roots, keys);
  std::vector<ExprRef> outs;
  for (const ir::SystemOutput &o : sys.outputs)
    outs.push_back(o.value);
  plan.nOutputs = outs.size();
  plan.outputs = valuesFunction("outputs", outs, keys);
  if (!sys.tested.empty()) {
    std::vector<ExprRef> tested;
    for (const ir::TestedValue &v : sys.tested) {
      tested.push_back(v.value);
      plan.testedNominal.push_back(v.nominal);
    }
    plan.tested = valuesFunction("tested", tested, keys);
    std::vector<JacEntry> entries = jacobianEntries(sys, tested, keys, diff);
    cscPattern(entries, n, plan.testedColptr, plan.testedRowind);
    plan.testedJacobianCsc = addFunction(
        "tested_jac_csc", FnSig::Jacobian, keys,
        [&](FunctionBuilder &b, PlanFunction &) {
          for (uint32_t k = 0; k < entries.size(); ++k)
            b.store(jacobianValue(b, entries[k]), 0, k, entries[k].row);
        });
  }
  plan.nDrift = sys.constraints.size();
  plan.drift = valuesFunction("drift", sys.constraints, keys);
  if (sys.form == ir::SystemForm::LinearlyImplicit)
    planGeometricSlots(sys, plan, diff, addFunction);
  EventFunctionValues events = eventFunctionValues(sys.events);
  if (!events.update.empty())
    plan.events.update = valuesFunction("event_update", events.update, keys);
  if (!events.timeEvents.empty())
    plan.events.timeEvents =
        valuesFunction("time_events", events.timeEvents, keys);
  if (!events.asserts.empty())
    plan.events.asserts = valuesFunction("asserts", events.asserts, keys);
  if (std::vector<ExprRef> values = planBindings(sys, plan); !values.empty())
    plan.bind = valuesFunction("bind", values, keys);
  if (std::vector<ExprRef> calls = planObjects(sys, plan); !calls.empty())
    plan.objects = valuesFunction("objects", calls, keys);
  if (sys.model)
    for (const ir::Model::CompileTimeCall &c : sys.model->compileTimeCalls) {
      PlanExternal x;
      x.symbol = c.symbol;
      x.numInputs = unsigned(c.inputs.size());
      x.numOutputs = c.outputs;
      x.objects = c.objects;
      plan.replays.push_back({std::move(x), c.inputs});
    }

  if (!error.empty())
    return Error{error};
  numberExternals(plan);
  return plan;
}

} // namespace ldae::codegen
