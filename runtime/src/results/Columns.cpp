// Result columns (see Columns.h).
#include "results/Columns.h"
#include "ldae/ResultWriter.h"

#include <cstring>
#include <fmt/format.h>
#include <unordered_map>
#include <unordered_set>

namespace ldae::runtime {

namespace {

bool isDerivative(const std::string &name) {
  return name.compare(0, 4, "der(") == 0;
}

std::string text(const char *const *table, int i) {
  return table && table[i] ? table[i] : "";
}

std::string paramName(const ldae_model &m, int k) {
  return m.param_names && m.param_names[k] ? m.param_names[k]
                                           : fmt::format("p[{}]", k);
}

} // namespace

Reportable::Reportable(const ldae_model &m) {
  const bool outputs = m.n_outputs > 0;
  sources = outputs ? m.n_outputs : m.n;
  for (int i = 0; i < sources; ++i) {
    const char *name = outputs ? m.output_names[i]
                               : (m.var_names ? m.var_names[i] : nullptr);
    names.push_back(name ? name : fmt::format("y[{}]", i));
  }
  for (int k = 0; k < m.n_params; ++k)
    names.push_back(paramName(m, k));
}

Expected<std::vector<int>>
chooseColumns(const ldae_model &m, const std::vector<std::string> &wanted) {
  Reportable all(m);
  if (!wanted.empty())
    return selectColumns(all.names, wanted);
  // der(x) is there for --outputs 'der(x)'; by default x suffices, and
  // homotopy()'s continuation parameter is the compiler's, not the user's.
  std::vector<int> cols;
  for (int c = 0; c < int(all.names.size()); ++c)
    if (c >= all.sources ? all.names[c] != LDAE_HOMOTOPY_LAMBDA
                         : !isDerivative(all.names[c]))
      cols.push_back(c);
  return cols;
}

std::vector<ColumnInfo> columnInfo(const ldae_model &m,
                                   const std::vector<int> &cols) {
  const int sources = m.n_outputs > 0 ? m.n_outputs : m.n;
  std::unordered_set<std::string> discrete;
  for (int k = 0; k < m.n_discrete; ++k)
    if (m.discrete_names && m.discrete_names[k] &&
        (!m.discrete_kind || m.discrete_kind[k] == LDAE_DISCRETE_VARIABLE))
      discrete.insert(m.discrete_names[k]);
  std::unordered_map<int, int> resultColumn; // output -> result column
  for (size_t i = 0; i < cols.size(); ++i)
    if (cols[i] < sources)
      resultColumn.emplace(cols[i], int(i) + 1);

  std::vector<ColumnInfo> info(1);
  info[0].kind = ColumnKind::Time;
  info[0].unit = "s";
  for (int c : cols) {
    ColumnInfo ci;
    if (c >= sources) {
      int k = c - sources;
      ci.kind = ColumnKind::Parameter;
      ci.unit = text(m.param_unit, k);
      ci.description = text(m.param_description, k);
    } else if (m.n_outputs > 0) {
      std::string name = m.output_names[c] ? m.output_names[c] : "";
      ci.kind = isDerivative(name)        ? ColumnKind::Derivative
                : discrete.count(name) > 0 ? ColumnKind::Discrete
                                           : ColumnKind::Continuous;
      ci.unit = text(m.output_unit, c);
      ci.description = text(m.output_description, c);
      if (int a = m.output_alias ? m.output_alias[c] : 0) {
        auto at = resultColumn.find(std::abs(a) - 1);
        if (at != resultColumn.end())
          ci.alias = a > 0 ? at->second + 1 : -(at->second + 1);
      }
    }
    info.push_back(std::move(ci));
  }
  return info;
}

std::vector<ParamValue> parameterValues(const ldae_model &m, const double *p) {
  std::vector<ParamValue> out;
  for (int k = 0; k < m.n_params; ++k)
    out.push_back({paramName(m, k), p[k], text(m.param_unit, k),
                   text(m.param_description, k)});
  return out;
}

} // namespace ldae::runtime
