// The columns of a result (docs/results.md, "Columns"): which values a
// run reports, in which order, and what a result file says of each.
#pragma once

#include "ldae/Simulation.h"
#include "ldae/model.h"

#include <string>
#include <vector>

namespace ldae::runtime {

/// What a model can report, indexed as a run's column indices: first its
/// outputs (or its unknowns when it has none: "sources"), then its
/// parameters (constant columns).
struct Reportable {
  explicit Reportable(const ldae_model &m);
  /// How many of `names` are outputs or unknowns; index i >= sources is
  /// parameter i - sources.
  int sources = 0;
  std::vector<std::string> names;
};

/// The column indices of a run: `wanted` by name (outputs, unknowns or
/// parameters; an unknown name is an Error listing close names), or by
/// default every output but the derivatives, then every parameter.
Expected<std::vector<int>> chooseColumns(const ldae_model &m,
                                         const std::vector<std::string> &wanted);

/// Column `c`'s value from the model's outputs (or unknowns) `src` and
/// the run's parameter vector `p`.
inline double columnValue(int c, int sources, const double *src,
                          const double *p) {
  return c < sources ? src[c] : p[c - sources];
}

/// What a result file says of "time" and each of `cols` (units,
/// descriptions, kinds; aliases mapped to result columns, 0 where the
/// column aliased is not reported).
std::vector<ColumnInfo> columnInfo(const ldae_model &m,
                                   const std::vector<int> &cols);

/// Every parameter of `m` with its value in `p` (the run's).
std::vector<ParamValue> parameterValues(const ldae_model &m, const double *p);

} // namespace ldae::runtime
