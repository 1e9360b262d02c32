// The integration methods of `--method` (DESIGN.md, "Integration
// methods") as the passes know them: each method has one pipeline
// (pipelineFor in Passes.h), and no pass asks which method is running.
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace ldae::passes {

enum class Method {
  DummyDerivatives, // dd: index reduction to an index-1 DAE (the default)
  Sga,              // sga: its own passes arrive with issue 14
  Ode,              // ode: its own passes arrive with issue 14
  Raw,              // raw: the model as written, no index reduction
};

/// The command-line spelling of each method, in the order of the enum.
inline constexpr std::array<std::string_view, 4> kMethodSpellings = {
    "dd", "sga", "ode", "raw"};

inline std::string_view methodSpelling(Method m) {
  return kMethodSpellings[static_cast<size_t>(m)];
}

/// The method spelled `s` on the command line, or nothing.
inline std::optional<Method> parseMethod(std::string_view s) {
  for (size_t i = 0; i < kMethodSpellings.size(); ++i)
    if (kMethodSpellings[i] == s)
      return static_cast<Method>(i);
  return std::nullopt;
}

} // namespace ldae::passes
