// Parsing the front ends' option words and mapping a run onto the
// runtime's options; see RunRequest.h.
#include "RunRequest.h"

#include <cmath>
#include <fmt/format.h>

namespace ldae::driver {

std::optional<bool> switchSetting(SwitchChoice choice) {
  switch (choice) {
  case SwitchChoice::Auto:
    return std::nullopt;
  case SwitchChoice::On:
    return true;
  case SwitchChoice::Off:
    return false;
  }
  return std::nullopt;
}

SwitchChoice switchChoice(std::optional<bool> setting) {
  if (!setting)
    return SwitchChoice::Auto;
  return *setting ? SwitchChoice::On : SwitchChoice::Off;
}

Expected<passes::Method> parseMethodOption(const std::string &text) {
  if (std::optional<passes::Method> m = passes::parseMethod(text))
    return *m;
  return Error{"unknown method '" + text + "' (dd, sga, ode or raw)"};
}

Expected<SwitchChoice> parseJitOption(const std::string &text) {
  if (std::optional<SwitchChoice> s = parseSpelling(kSwitchSpellings, text))
    return *s;
  return Error{"jit must be 'on', 'off' or 'auto', not '" + text + "'"};
}

Expected<runtime::IntegratorChoice>
parseIntegratorOption(const std::string &text) {
  if (std::optional<runtime::IntegratorChoice> i =
          runtime::parseIntegrator(text))
    return *i;
  return Error{"unknown integrator '" + text +
               "' (auto, ida, cvode, cvode-bdf, cvode-adams)"};
}

void applyCompileChoices(const CompileChoices &choices,
                         CompileRequest &request) {
  request.passes.method = choices.method;
  // Unset: chosen by the size of the model.
  request.codegen.jit = switchSetting(choices.jit);
  request.codegen.cacheDir = choices.cacheDir;
}

Expected<bool> checkFinite(const RunRequest &run) {
  for (const auto &[what, map] :
       {std::pair{"parameter override", &run.params},
        std::pair{"start value override", &run.starts}})
    for (const auto &[name, value] : *map)
      if (!std::isfinite(value))
        return Error{fmt::format("invalid {} '{}={}': '{}' is not a number",
                                 what, name, value, value)};
  for (const auto &[option, value] :
       {std::pair{"start", run.start}, std::pair{"stop", run.stop},
        std::pair{"rtol", run.rtol}, std::pair{"atol", run.atol},
        std::pair{"interval", run.interval}})
    if (value && !std::isfinite(*value))
      return Error{
          fmt::format("invalid {} '{}': not a finite number", option, *value)};
  for (double t : run.times)
    if (!std::isfinite(t))
      return Error{
          fmt::format("invalid output time '{}': not a finite number", t)};
  return true;
}

runtime::SimOptions runOptions(const RunRequest &run,
                               const CompileRequest &compile) {
  runtime::SimOptions o;
  o.start = run.start;
  o.stop = run.stop;
  o.rtol = run.rtol;
  o.atol = run.atol;
  o.interval = run.interval;
  o.everyStep = run.everyStep;
  o.times = run.times;
  // The selected names in model order; none: the runtime's default columns.
  o.outputs = run.outputs.empty() ? compile.passes.outputs : run.outputs;
  o.integrator = run.integrator;
  o.algebraicErrorTest = switchSetting(run.algebraicErrorTest);
  o.params = run.params;
  o.starts = run.starts;
  o.progress = run.progress;
  return o;
}

} // namespace ldae::driver
