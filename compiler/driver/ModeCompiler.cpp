#include "ModeCompiler.h"

#include "ir/Query.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

namespace ldae::driver {

const ir::Equation *firstVariableIf(const ir::Model &flat) {
  auto readsZeroParameter = [&](ir::ExprRef e) {
    for (ir::ParamId p : ir::freeParameters(e))
      if (p < flat.parameters.size() && flat.parameters[p].value == 0.0)
        return true;
    return false;
  };
  for (const ir::Equation &e : flat.equations) {
    if (e.residual->kind() == ir::ExprKind::If)
      return &e;
    for (ir::ExprRef n : ir::topologicalOrder(std::span(&e.residual, 1)))
      if (n->kind() == ir::ExprKind::If && !n->operand(0)->isConstant() &&
          (readsZeroParameter(n->operand(1)) ||
           readsZeroParameter(n->operand(2))))
        return &e;
  }
  return nullptr;
}

ModeCompiler::ModeCompiler(const ir::Model &flat,
                           passes::PipelineOptions passOpts,
                           codegen::CodegenOptions cgOpts,
                           DiagnosticEngine &diags)
    : flat_(flat), passOpts_(std::move(passOpts)), cgOpts_(std::move(cgOpts)),
      diags_(diags) {
  // A mode the run reaches starts from the point the run carries over
  // (the jump rule, reinit values held), not from the start values: fixed
  // start values and initial equations are conditions of the start only,
  // and would contradict a mode that ties them (two capacitors joined).
  for (ir::Variable &v : flat_.variables)
    v.fixed = false;
  flat_.initialEquations.clear();
  // A mode's report is not printed, and its printing of passes would
  // repeat the first mode's.
  passOpts_.reportOnly = false;
  passOpts_.printAfter.clear();
  passOpts_.timePasses = false;
  passOpts_.keepStateAliases = true;
}

Expected<ModeCompiler::Mode *>
ModeCompiler::analyzed(const std::vector<double> &values) {
  if (auto it = modes_.find(values); it != modes_.end())
    return &it->second;
  auto t0 = std::chrono::steady_clock::now();
  Mode mode;
  mode.model = std::make_unique<ir::Model>(flat_);
  passes::PipelineOptions opts = passOpts_;
  opts.modeValues = values;
  // The diagnostics of this mode alone: a failure says why it has no
  // system (a structurally singular mode names its equations).
  size_t before = diags_.diagnostics().size();
  bool ok = passes::runPipeline(*mode.model, opts, diags_, mode.analysis);
  std::string text;
  for (size_t i = before; i < diags_.diagnostics().size(); ++i)
    text += diags_.render(diags_.diagnostics()[i]);
  if (!ok || !mode.analysis.system)
    return Error{fmt::format("the mode cannot be analysed:\n{}", text)};
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                            t0)
                  .count();
  auto [it, inserted] = modes_.emplace(values, std::move(mode));
  return &it->second;
}

Expected<const ldae_model *>
ModeCompiler::model(const std::vector<double> &values) {
  auto mode = analyzed(values);
  if (!mode)
    return Error{mode.error()};
  Mode &m = **mode;
  if (!m.code) {
    auto t0 = std::chrono::steady_clock::now();
    auto code = codegen::compile(*m.analysis.system, cgOpts_);
    if (!code)
      return Error{
          fmt::format("the mode cannot be compiled: {}", code.error())};
    m.code = std::move(*code);
    seconds_ += std::chrono::duration<double>(
                    std::chrono::steady_clock::now() - t0)
                    .count();
  }
  return &m.code->model();
}

Expected<const ir::DaeSystem *>
ModeCompiler::system(const std::vector<double> &values) {
  auto mode = analyzed(values);
  if (!mode)
    return Error{mode.error()};
  return &*(*mode)->analysis.system;
}

Expected<std::vector<std::vector<double>>>
ModeCompiler::allModes(const ir::EventSystem &events) const {
  std::vector<std::vector<double>> ranges;
  size_t count = 1;
  for (uint32_t k : events.modeDiscrete) {
    const ir::DiscreteValue &d = events.discrete[k];
    std::vector<double> range{0, 1}; // a Boolean, a relation
    if (d.kind == ir::DiscreteKind::Variable) {
      std::optional<ir::VarId> v = flat_.findVariable(d.name);
      const ir::Variable *var = v ? &flat_.variables[*v] : nullptr;
      if (var && var->isInteger) {
        if (!std::isfinite(var->min) || !std::isfinite(var->max) ||
            var->max - var->min >= double(kMaxModesAhead))
          return Error{fmt::format(
              "the mode value '{}' is an Integer without a range of at most "
              "{} values (min and max)",
              d.name, kMaxModesAhead)};
        range.clear();
        for (double x = var->min; x <= var->max; ++x)
          range.push_back(x);
      } else if (var && !var->isBoolean) {
        return Error{fmt::format("the mode value '{}' is not a Boolean or an "
                                 "Integer",
                                 d.name)};
      }
    }
    count *= range.size();
    if (count > kMaxModesAhead)
      return Error{fmt::format("the mode values {} give more than {} modes",
                               events.modeDiscrete.size(), kMaxModesAhead)};
    ranges.push_back(std::move(range));
  }
  std::vector<std::vector<double>> modes(1);
  for (const std::vector<double> &range : ranges) {
    std::vector<std::vector<double>> longer;
    for (const std::vector<double> &m : modes)
      for (double x : range) {
        longer.push_back(m);
        longer.back().push_back(x);
      }
    modes = std::move(longer);
  }
  return modes;
}

} // namespace ldae::driver
