// Plan evaluation and the fixed thunk table; see Interpreter.h. The value
// semantics of every operation are docs/codegen.md's; the LLVM and C
// backends encode the same formulas.
#include "codegen/Interpreter.h"

#include "ir/Evaluate.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <utility>

namespace ldae::codegen {

using ir::CompareKind;
using ir::FuncKind;

namespace {

double func1(FuncKind f, double a) {
  switch (f) {
  case FuncKind::Sin: return std::sin(a);
  case FuncKind::Cos: return std::cos(a);
  case FuncKind::Tan: return std::tan(a);
  case FuncKind::Asin: return std::asin(a);
  case FuncKind::Acos: return std::acos(a);
  case FuncKind::Atan: return std::atan(a);
  case FuncKind::Sinh: return std::sinh(a);
  case FuncKind::Cosh: return std::cosh(a);
  case FuncKind::Tanh: return std::tanh(a);
  case FuncKind::Exp: return std::exp(a);
  case FuncKind::Log: return std::log(a);
  case FuncKind::Log10: return std::log10(a);
  case FuncKind::Sqrt: return std::sqrt(a);
  case FuncKind::Abs: return std::fabs(a);
  case FuncKind::Sign: return double(a > 0) - double(a < 0);
  case FuncKind::Floor: return std::floor(a);
  case FuncKind::Ceil: return std::ceil(a);
  default: break;
  }
  assert(false && "not a unary built-in");
  return 0;
}

double func2(FuncKind f, double a, double b) {
  switch (f) {
  case FuncKind::Atan2: return std::atan2(a, b);
  case FuncKind::Min: return a < b ? a : b;
  case FuncKind::Max: return a > b ? a : b;
  case FuncKind::Mod: return a - std::floor(a / b) * b;
  default: break;
  }
  assert(false && "not a binary built-in");
  return 0;
}

bool compare(CompareKind c, double a, double b) {
  switch (c) {
  case CompareKind::Lt: return a < b;
  case CompareKind::Le: return a <= b;
  case CompareKind::Gt: return a > b;
  case CompareKind::Ge: return a >= b;
  case CompareKind::Eq: return a == b;
  case CompareKind::Ne: return a != b;
  }
  return false;
}

double powInt(double x, int32_t k) {
  double result = 0, base = x;
  bool have = false;
  for (PowIntStep s : powIntSteps(k)) {
    if (s.multiplyResult) {
      result = have ? result * base : base;
      have = true;
    }
    if (s.squareBase)
      base = base * base;
  }
  return result;
}

/// The domain check of a node with `checks` set.
bool domainError(const PlanNode &n, double a, double b) {
  switch (n.op) {
  case OpCode::Div: return b == 0;
  case OpCode::Sqrt: return a < 0;
  case OpCode::Pow: return (a < 0 && std::floor(b) != b) || (a == 0 && b < 0);
  case OpCode::Func1:
    if (FuncKind(n.sub) == FuncKind::Log || FuncKind(n.sub) == FuncKind::Log10)
      return !(a > 0);
    return std::fabs(a) > 1; // asin, acos
  case OpCode::Func2: return b == 0; // mod
  default: return false;
  }
}

void evaluateNodes(const PlanFunction &fn, double t, const double *y,
                   const double *yp, const double *p, double cj,
                   const int64_t *columns, double *v, uint8_t *err);

/// Folds the terms of reduction `r` into `acc`; sets `failed` when a term
/// hit a domain error.
double reduce(const PlanLoop &r, double acc, double t, const double *y,
              const double *yp, const double *p, double cj, bool &failed) {
  // Loop bodies hold no Reduce, so these buffers are never in use twice.
  thread_local std::vector<double> v;
  thread_local std::vector<uint8_t> err;
  thread_local std::vector<int64_t> columns;
  v.resize(r.body.nodes.size());
  err.resize(r.body.nodes.size());
  columns.resize(r.columns.size());
  const size_t root = r.body.nodes.size() - 1;
  for (uint32_t i = 0; i < r.count; ++i) {
    for (size_t c = 0; c < r.columns.size(); ++c)
      columns[c] = r.columns[c].at(i);
    evaluateNodes(r.body, t, y, yp, p, cj, columns.data(), v.data(),
                  err.data());
    acc = r.subtract ? acc - v[root] : acc + v[root];
    failed = failed || err[root];
  }
  return acc;
}

/// Evaluates the nodes of `fn` into v and err. In a loop body `columns`
/// holds the iteration's index columns, which load indices name.
void evaluateNodes(const PlanFunction &fn, double t, const double *y,
                   const double *yp, const double *p, double cj,
                   const int64_t *columns, double *v, uint8_t *err) {
  auto slot = [&](int32_t i) { return columns ? columns[i] : int64_t(i); };
  const size_t size = fn.nodes.size();
  for (size_t k = 0; k < size; ++k) {
    const PlanNode &n = fn.nodes[k];
    double a = 0, b = 0, r = 0;
    if (!isLeaf(n.op)) {
      a = v[n.a];
      b = v[n.b];
    }
    switch (n.op) {
    case OpCode::Const: r = n.value; break;
    case OpCode::LoadY: r = y[slot(n.index)]; break;
    case OpCode::LoadYp: r = yp[slot(n.index)]; break;
    case OpCode::LoadP: r = p[slot(n.index)]; break;
    case OpCode::Time: r = t; break;
    case OpCode::Cj: r = cj; break;
    case OpCode::Add: r = a + b; break;
    case OpCode::Sub: r = a - b; break;
    case OpCode::Mul: r = a * b; break;
    case OpCode::Div: r = a / b; break;
    case OpCode::Neg: r = -a; break;
    case OpCode::PowInt: r = powInt(a, n.index); break;
    case OpCode::Pow: r = std::pow(a, b); break;
    case OpCode::Sqrt: r = std::sqrt(a); break;
    case OpCode::Func1: r = func1(FuncKind(n.sub), a); break;
    case OpCode::Func2: r = func2(FuncKind(n.sub), a, b); break;
    case OpCode::Select: r = a != 0 ? b : v[n.c]; break;
    case OpCode::Compare: r = compare(CompareKind(n.sub), a, b); break;
    case OpCode::And: r = a != 0 && b != 0; break;
    case OpCode::Or: r = a != 0 || b != 0; break;
    case OpCode::Not: r = a == 0; break;
    case OpCode::ExtArg: r = a; break;
    case OpCode::ExtCall: {
      if (n.sub == 1 && v[n.b] == 0) { // a branch not taken
        r = 0;
        break;
      }
      const PlanExternal &f = fn.externals[n.index];
      std::vector<uint32_t> args = externalArguments(fn.nodes, uint32_t(k));
      std::vector<double> in(args.size()), out(std::max(1u, f.numOutputs));
      for (size_t i = 0; i < args.size(); ++i)
        in[i] = v[args[i]];
      reinterpret_cast<void (*)(const double *, double *)>(f.address)(
          in.data(), out.data());
      r = out[size_t(n.value)];
      break;
    }
    case OpCode::Reduce: {
      bool failed = err[n.a];
      v[k] = reduce(fn.reductions[n.index], a, t, y, yp, p, cj, failed);
      err[k] = failed;
      continue;
    }
    }
    v[k] = r;
    if (n.mayFail) {
      bool e;
      if (n.op == OpCode::Select)
        e = err[n.a] || (a != 0 ? err[n.b] : err[n.c]);
      else if (n.op == OpCode::And) // b matters only when a holds
        e = err[n.a] || (a != 0 && err[n.b]);
      else if (n.op == OpCode::Or)
        e = err[n.a] || (a == 0 && err[n.b]);
      else {
        e = n.checks && (n.op == OpCode::ExtCall ? std::isnan(r)
                                                 : domainError(n, a, b));
        for (unsigned i = 0; i < numOperands(n.op); ++i)
          e = e || err[n.operand(i)];
      }
      err[k] = e;
    } else {
      err[k] = 0;
    }
  }
}

/// Writes the stores of `fn`; returns `rc`, or 1 + the row of the first
/// failing store when `rc` is 0.
int storeValues(const PlanFunction &fn, const int64_t *columns,
                const double *v, const uint8_t *err, double *out0,
                double *out1, int rc) {
  auto slot = [&](uint32_t i) { return columns ? columns[i] : int64_t(i); };
  for (const PlanStore &s : fn.stores) {
    (s.array ? out1 : out0)[slot(s.index)] = v[s.node];
    if (!rc && err[s.node])
      rc = 1 + int(slot(s.row));
  }
  return rc;
}

} // namespace

int interpret(const PlanFunction &fn, double t, const double *y,
              const double *yp, const double *p, double cj, double *out0,
              double *out1) {
  thread_local std::vector<double> v;
  thread_local std::vector<uint8_t> err;
  thread_local std::vector<int64_t> columns;
  size_t size = fn.nodes.size();
  for (const PlanLoop &l : fn.loops)
    size = std::max(size, l.body.nodes.size());
  if (v.size() < size) {
    v.resize(size);
    err.resize(size);
  }
  evaluateNodes(fn, t, y, yp, p, cj, nullptr, v.data(), err.data());
  for (unsigned i = 0; i < 2; ++i)
    if (double *out = i ? out1 : out0)
      std::fill(out, out + fn.zeroFill[i], 0.0);
  int rc = storeValues(fn, nullptr, v.data(), err.data(), out0, out1, 0);
  for (const PlanLoop &l : fn.loops) {
    if (rc)
      break; // as the compiled code: loops run while no error was returned
    columns.resize(l.columns.size());
    for (uint32_t i = 0; i < l.count; ++i) {
      for (size_t c = 0; c < l.columns.size(); ++c)
        columns[c] = l.columns[c].at(i);
      evaluateNodes(l.body, t, y, yp, p, cj, columns.data(), v.data(),
                    err.data());
      rc = storeValues(l.body, columns.data(), v.data(), err.data(), out0,
                       out1, rc);
    }
  }
  return rc;
}

namespace {

std::array<std::atomic<const PlanFunction *>, kInterpreterSlots> gSlots;
std::mutex gSlotMutex;

template <size_t S>
int valuesThunk(double t, const double *y, const double *yp, const double *p,
                double *out) {
  return interpret(*gSlots[S].load(std::memory_order_relaxed), t, y, yp, p, 0,
                   out, nullptr);
}
template <size_t S>
int jacobianThunk(double t, const double *y, const double *yp,
                  const double *p, double cj, double *out) {
  return interpret(*gSlots[S].load(std::memory_order_relaxed), t, y, yp, p, cj,
                   out, nullptr);
}
template <size_t S>
int initJacobianThunk(double t, const double *y, const double *yp,
                      const double *p, double *out0, double *out1) {
  return interpret(*gSlots[S].load(std::memory_order_relaxed), t, y, yp, p, 0,
                   out0, out1);
}

/// A function over (t, y) only: y stands in for the never-read yp.
template <size_t S>
int stateThunk(double t, const double *y, const double *p, double *out) {
  return interpret(*gSlots[S].load(std::memory_order_relaxed), t, y, y, p, 0,
                   out, nullptr);
}

template <size_t... S>
constexpr auto makeThunks(std::index_sequence<S...>) {
  return std::array<std::array<uintptr_t, 4>, sizeof...(S)>{
      {{reinterpret_cast<uintptr_t>(&valuesThunk<S>),
        reinterpret_cast<uintptr_t>(&jacobianThunk<S>),
        reinterpret_cast<uintptr_t>(&initJacobianThunk<S>),
        reinterpret_cast<uintptr_t>(&stateThunk<S>)}...}};
}

const auto gThunks = makeThunks(std::make_index_sequence<kInterpreterSlots>());

} // namespace

Expected<uintptr_t> bindInterpreterSlot(const PlanFunction &fn,
                                        unsigned &slot) {
  std::lock_guard<std::mutex> lock(gSlotMutex);
  for (unsigned s = 0; s < kInterpreterSlots; ++s) {
    if (gSlots[s].load() != nullptr)
      continue;
    gSlots[s].store(&fn);
    slot = s;
    return gThunks[s][unsigned(fn.sig)];
  }
  return Error{"too many interpreted functions alive at once (the limit is " +
               std::to_string(kInterpreterSlots) + ")"};
}

void releaseInterpreterSlot(unsigned slot) {
  std::lock_guard<std::mutex> lock(gSlotMutex);
  gSlots[slot].store(nullptr);
}

} // namespace ldae::codegen
