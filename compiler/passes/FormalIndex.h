// Le Vey's formal index (seed 004) of a flat model as written: the number
// of prolongation–projection steps that make it formally integrable. The
// "formal-index" pass reports it; benchmarks call it directly with another
// size limit. See FormalIndex.cpp and docs/indices.md.
#pragma once

#include "ir/Model.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace ldae::passes {

/// Jet coordinates of J_q (continuous unknowns times q + 1) above which the
/// dense rank tests are not attempted and the report gives `null`
/// (docs/indices.md has the measured cost of a 1,000-unknown model).
inline constexpr size_t kFormalIndexMaxCoordinates = 200;

struct FormalIndexResult {
  std::optional<int> index;
  std::string reason;          ///< why there is no index, "" otherwise
  std::vector<int> dimensions; ///< dim R_q^(s) in J_q, s = 0, 1, ...
};

FormalIndexResult formalIndex(
    const ir::Model &model,
    size_t maxCoordinates = kFormalIndexMaxCoordinates);

} // namespace ldae::passes
