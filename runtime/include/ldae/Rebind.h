// A compiled model run with other parameter and start values than it was
// compiled with (SimOptions::params, ::starts; the emitted main's --param):
// what reads a changed parameter is evaluated again through the model's
// bind function (ldae_model's run-time parameters block), so the run
// computes what recompiling with `ldaec --param` would.
#pragma once

#include "ldae/model.h"
#include "support/Expected.h"

#include <map>
#include <string>
#include <vector>

namespace ldae::runtime {

/// The parameter and start vectors of one run.
struct BoundValues {
  std::vector<double> p; ///< n_params
  std::vector<double> y; ///< n: start_y with the changed start values
  /// Set when a binding left its domain for these values (a numerical
  /// failure of the run, status 3); p and y are then incomplete.
  std::string failure;
};

/// Applies `params` (by parameter name) and `starts` (by unknown name) to
/// the model's defaults at the start time `t0`: the bound parameters not
/// given (one pass per level of a chain of bindings), then the start
/// values bound to parameters that `starts` does not give. An Error (a bad
/// request: exit 2, a Python exception) for an unknown name (listing close
/// names), a structural parameter, or a start value that is no unknown of
/// the compiled model.
Expected<BoundValues> bindValues(const ldae_model &m,
                                 const std::map<std::string, double> &params,
                                 const std::map<std::string, double> &starts,
                                 double t0);

/// ldae_model::param_structural of a constant.
inline constexpr int kConstantParameter = 2;

/// Why parameter k (param_structural[k] != 0) cannot change at run time:
/// it fixed the model's structure, or it is a constant.
std::string structuralParameterMessage(const ldae_model &m, int k);

} // namespace ldae::runtime
