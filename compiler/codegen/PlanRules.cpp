// The conventions every backend follows when it turns a plan into code:
// symbol names, the C math function of each built-in, the power schedule,
// the size of a plan. Compiled into ldae_codegen and into the JIT module
// (libldae_jit.so), which shares no other code with the executable.
#include "codegen/CodePlan.h"

#include <algorithm>

#include <cassert>

namespace ldae::codegen {

using ir::FuncKind;

const char *cMathName(FuncKind f) {
  switch (f) {
  case FuncKind::Sin: return "sin";
  case FuncKind::Cos: return "cos";
  case FuncKind::Tan: return "tan";
  case FuncKind::Asin: return "asin";
  case FuncKind::Acos: return "acos";
  case FuncKind::Atan: return "atan";
  case FuncKind::Atan2: return "atan2";
  case FuncKind::Sinh: return "sinh";
  case FuncKind::Cosh: return "cosh";
  case FuncKind::Tanh: return "tanh";
  case FuncKind::Exp: return "exp";
  case FuncKind::Log: return "log";
  case FuncKind::Log10: return "log10";
  case FuncKind::Sqrt: return "sqrt";
  case FuncKind::Abs: return "fabs";
  case FuncKind::Floor: return "floor";
  case FuncKind::Ceil: return "ceil";
  default: return nullptr;
  }
}

PowIntSchedule powIntSteps(int32_t k) {
  assert(k >= 1);
  PowIntSchedule s;
  while (k) {
    bool mul = k & 1;
    k >>= 1;
    s.steps[s.size++] = {mul, k != 0};
  }
  return s;
}

std::string functionSymbol(const CodePlan &plan, const PlanFunction &fn) {
  return plan.symbolName + "_" + fn.name;
}

size_t planWork(const CodePlan &plan) {
  size_t n = 0;
  for (const PlanFunction &fn : plan.functions) {
    n += fn.nodes.size();
    for (const PlanLoop &l : fn.loops)
      n += size_t(l.count) * l.body.nodes.size();
    for (const PlanLoop &r : fn.reductions)
      n += size_t(r.count) * r.body.nodes.size();
  }
  return n;
}

size_t planNodes(const CodePlan &plan) {
  size_t n = 0;
  for (const PlanFunction &fn : plan.functions) {
    n += fn.nodes.size();
    for (const PlanLoop &l : fn.loops)
      n += l.body.nodes.size();
    for (const PlanLoop &r : fn.reductions)
      n += r.body.nodes.size();
  }
  return n;
}

std::vector<uint32_t> externalArguments(std::span<const PlanNode> nodes,
                                        uint32_t call) {
  std::vector<uint32_t> args;
  uint32_t k = nodes[call].a;
  if (nodes[k].op != OpCode::ExtArg)
    return args;
  for (;;) {
    args.push_back(k);
    if (nodes[k].index == 0)
      break;
    k = nodes[k].b;
  }
  std::reverse(args.begin(), args.end());
  return args;
}

} // namespace ldae::codegen
