// The two CompiledModel backends (JIT, interpreter) and the text emitters,
// each a thin layer over lowerToPlan.
#include "codegen/Codegen.h"

#include "codegen/CEmitter.h"
#include "codegen/Interpreter.h"
#include "codegen/LlvmEmitter.h"
#include "codegen/ModelTables.h"

namespace ldae::codegen {

CompiledModel::~CompiledModel() = default;

namespace {

PlanOptions planOptions(const CodegenOptions &opts) {
  PlanOptions p;
  p.chunkSize = opts.chunkSize;
  p.loops = opts.loops;
  p.sources = opts.sources;
  return p;
}

class JitModel : public CompiledModel {
public:
  JitModel(const CodePlan &plan, std::unique_ptr<JitCode> code)
      : code_(std::move(code)), tables_(plan) {
    tables_.setFunctions(plan, [&](int i) { return code_->address(i); });
  }
  const ldae_model &model() const override { return tables_.model(); }

private:
  std::unique_ptr<JitCode> code_;
  ModelTables tables_;
};

class InterpretedModel : public CompiledModel {
public:
  explicit InterpretedModel(CodePlan plan)
      : plan_(std::move(plan)), tables_(plan_) {}
  ~InterpretedModel() override {
    for (unsigned s : slots_)
      releaseInterpreterSlot(s);
  }
  /// Binds every plan function to a thunk slot.
  Expected<bool> bind() {
    std::vector<uintptr_t> addresses;
    for (const PlanFunction &fn : plan_.functions) {
      unsigned slot;
      auto addr = bindInterpreterSlot(fn, slot);
      if (!addr)
        return Error{addr.error()};
      slots_.push_back(slot);
      addresses.push_back(*addr);
    }
    tables_.setFunctions(plan_, [&](int i) { return addresses[i]; });
    return true;
  }
  const ldae_model &model() const override { return tables_.model(); }

private:
  CodePlan plan_;
  ModelTables tables_;
  std::vector<unsigned> slots_;
};

} // namespace

Expected<std::unique_ptr<CompiledModel>> compile(const ir::DaeSystem &sys,
                                                 const CodegenOptions &opts) {
  auto plan = lowerToPlan(sys, planOptions(opts));
  if (!plan)
    return Error{plan.error()};
  if (opts.jit) {
    auto code = jitCompile(*plan);
    if (!code)
      return Error{code.error()};
    return std::unique_ptr<CompiledModel>(
        std::make_unique<JitModel>(*plan, std::move(*code)));
  }
  auto model = std::make_unique<InterpretedModel>(std::move(*plan));
  if (auto ok = model->bind(); !ok)
    return Error{ok.error()};
  return std::unique_ptr<CompiledModel>(std::move(model));
}

Expected<std::string> emitLlvm(const ir::DaeSystem &sys,
                               const CodegenOptions &opts) {
  auto plan = lowerToPlan(sys, planOptions(opts));
  if (!plan)
    return Error{plan.error()};
  return printModule(*plan);
}

Expected<std::string> emitC(const ir::DaeSystem &sys, bool withMain,
                            const CodegenOptions &opts) {
  PlanOptions po = planOptions(opts);
  po.bindings = withMain; // the main's --param re-binds parameters
  auto plan = lowerToPlan(sys, po);
  if (!plan)
    return Error{plan.error()};
  return printC(*plan, withMain);
}

} // namespace ldae::codegen
