// Which variables a run reports (--outputs, the Python module's
// `outputs=`): names and patterns expanded against the flat model, or
// against the names a compiled model reports (one run's `outputs=`).
#pragma once

#include "ir/Model.h"
#include "support/Expected.h"
#include "support/Diagnostics.h"

#include <optional>
#include <string>
#include <vector>

namespace ldae::driver {

/// The names `patterns` select, in model order (the variables in the order
/// of declaration, array elements by index, der(x) right after x, then the
/// parameters in the order of declaration), each once. A pattern is a flat name (`x`, `r1.v`,
/// `der(x)`, a parameter) or a glob where `*` matches any run of
/// characters and `?` one (`C[*].v`, `r1.*`). A name or pattern that
/// selects nothing is reported (ErrUnknownOutputOption, or
/// ErrUnknownOutputOptionSuggest with the closest names as
/// runtime::closeNames finds them; this replaces the driver's former
/// checkAgainstModel) and the result is nullopt.
std::optional<std::vector<std::string>>
selectOutputs(const ir::Model &model, const std::vector<std::string> &patterns,
              DiagnosticEngine &diags);

/// The names `patterns` select among `available`, the names a compiled
/// model reports in its order (the Python module's `outputs=` of one run):
/// a glob its matches in that order, a plain name itself (the runtime
/// names an unknown one, with close names), each name once, in the order
/// of the patterns. An Error for a glob that selects nothing.
Expected<std::vector<std::string>>
expandOutputPatterns(const std::vector<std::string> &patterns,
                     const std::vector<std::string> &available);

} // namespace ldae::driver
