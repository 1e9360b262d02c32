// The two CompiledModel backends (JIT, interpreter) and the text emitters,
// each a thin layer over lowerToPlan.
#include "codegen/Codegen.h"

#include "codegen/CEmitter.h"
#include "codegen/Interpreter.h"
#include "codegen/JitBackend.h"
#include "codegen/ModelTables.h"
#include "codegen/PlanLowering.h"

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
  JitModel(const CodePlan &plan, std::unique_ptr<JitCode> code,
           const BackendChoice &choice)
      : code_(std::move(code)), tables_(plan) {
    backend_ = choice;
    tables_.setFunctions(plan, [&](int i) { return code_->address(i); });
  }
  const ldae_model &model() const override { return tables_.model(); }

private:
  std::unique_ptr<JitCode> code_;
  ModelTables tables_;
};

class InterpretedModel : public CompiledModel {
public:
  InterpretedModel(CodePlan plan, const BackendChoice &choice)
      : plan_(std::move(plan)), tables_(plan_) {
    backend_ = choice;
  }
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
  BackendChoice choice;
  choice.automatic = !opts.jit.has_value();
  choice.work = planWork(*plan);
  choice.jit = opts.jit.value_or(choice.work > kAutoJitWork);
  std::unique_ptr<CompiledModel> model;
  if (choice.jit) {
    auto code = jitCompile(*plan, opts.cacheDir);
    if (!code)
      return Error{code.error()};
    if ((*code)->cache != CacheUse::None) {
      choice.cache = (*code)->cache == CacheUse::Hit ? "hit" : "miss";
      choice.cacheDir = opts.cacheDir;
    }
    model = std::make_unique<JitModel>(*plan, std::move(*code), choice);
  } else {
    auto interpreted = std::make_unique<InterpretedModel>(std::move(*plan), choice);
    if (auto ok = interpreted->bind(); !ok)
      return Error{ok.error()};
    model = std::move(interpreted);
  }
  return model;
}

std::string describeBackend(const BackendChoice &choice) {
  std::string line = choice.jit ? "backend: LLVM JIT" : "backend: interpreter";
  if (choice.automatic)
    line += " (--jit auto: " + std::to_string(choice.work) +
            " operations per evaluation, the JIT above " +
            std::to_string(kAutoJitWork) + ")";
  if (!choice.cache.empty())
    line += "\nobject cache: " + choice.cache + " (" + choice.cacheDir + ")";
  return line;
}

Expected<std::string> emitLlvm(const ir::DaeSystem &sys,
                               const CodegenOptions &opts) {
  auto plan = lowerToPlan(sys, planOptions(opts));
  if (!plan)
    return Error{plan.error()};
  return printModule(*plan);
}

Expected<std::string> emitC(const ir::DaeSystem &sys, bool withMain,
                            const CodegenOptions &opts,
                            const std::vector<ModeSystem> &modes) {
  auto plan = lowerToPlan(sys, planOptions(opts));
  if (!plan)
    return Error{plan.error()};
  if (!plan->unmadeObject.empty())
    return Error{"the external object '" + plan->unmadeObject +
                 "' cannot be made again by an emitted program"};
  std::vector<ModePlan> modePlans;
  for (const ModeSystem &m : modes) {
    auto modePlan = lowerToPlan(*m.system, planOptions(opts));
    if (!modePlan)
      return Error{modePlan.error()};
    // The start's model makes the objects and hands every mode the same
    // handles, at the same parameters.
    if (modePlan->objectParams != plan->objectParams)
      return Error{"a mode's external objects differ from the start's"};
    modePlan->symbolName =
        plan->symbolName + "_mode" + std::to_string(modePlans.size());
    modePlans.push_back({m.values, std::move(*modePlan)});
  }
  return printC(*plan, withMain, modePlans);
}

} // namespace ldae::codegen
