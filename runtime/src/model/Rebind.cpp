// Evaluating a model's parameter bindings again for a run; see Rebind.h.
#include "ldae/Rebind.h"

#include "ldae/ResultWriter.h"

#include <algorithm>
#include <cstring>
#include <fmt/format.h>

namespace ldae::runtime {

namespace {

std::vector<std::string> nameList(const char *const *names, int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i)
    out.push_back(names && names[i] ? names[i] : "");
  return out;
}

int indexOf(const std::vector<std::string> &names, const std::string &name) {
  auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

/// Why the start value of reported variable `name` (output k, no unknown)
/// needs a recompile.
Error computedStartError(const ldae_model &m, int k, const std::string &name) {
  std::string how = "solved out by the analysis";
  if (m.output_alias && m.output_alias[k] != 0) {
    int j = std::abs(m.output_alias[k]) - 1;
    how = fmt::format("an alias: {} = {}{}", name,
                      m.output_alias[k] < 0 ? "-" : "", m.output_names[j]);
  } else if (m.output_origin && m.output_origin[k] && *m.output_origin[k]) {
    how = fmt::format("by the equation at {}", m.output_origin[k]);
  }
  return Error{fmt::format("the start value of '{}' cannot change without "
                           "recompiling: {} is computed from other unknowns "
                           "({})",
                           name, name, how)};
}

/// Where each name of `starts` is among the unknowns.
Expected<std::vector<std::pair<int, double>>>
startIndices(const ldae_model &m, const std::map<std::string, double> &starts) {
  std::vector<std::pair<int, double>> out;
  if (starts.empty())
    return out;
  std::vector<std::string> vars = nameList(m.var_names, m.n);
  std::vector<std::string> outputs = nameList(m.output_names, m.n_outputs);
  for (const auto &[name, value] : starts) {
    if (int i = indexOf(vars, name); i >= 0) {
      out.emplace_back(i, value);
      continue;
    }
    if (int k = indexOf(outputs, name); k >= 0)
      return computedStartError(m, k, name);
    return unknownNameError("variable", name, vars);
  }
  return out;
}

} // namespace

std::string structuralParameterMessage(const ldae_model &m, int k) {
  std::string name = m.param_names[k];
  if (m.param_structural[k] == kConstantParameter)
    return fmt::format("cannot override constant '{}'", name);
  return fmt::format("parameter '{}' fixes the model's structure (an array "
                     "size, a branch or a subscript): it cannot change "
                     "without recompiling",
                     name);
}

Expected<BoundValues> bindValues(const ldae_model &m,
                                 const std::map<std::string, double> &params,
                                 const std::map<std::string, double> &starts,
                                 double t0) {
  BoundValues v;
  v.p.assign(m.param_values, m.param_values + m.n_params);
  v.y.assign(m.start_y, m.start_y + m.n);
  std::vector<char> given(m.n_params, 0);
  if (!params.empty()) {
    std::vector<std::string> names = nameList(m.param_names, m.n_params);
    for (const auto &[name, value] : params) {
      int k = indexOf(names, name);
      if (k < 0)
        return unknownNameError("parameter", name, names);
      if (m.param_structural && m.param_structural[k])
        return Error{structuralParameterMessage(m, k)};
      v.p[k] = value;
      given[k] = 1;
    }
  }
  auto startAt = startIndices(m, starts);
  if (!startAt)
    return Error{startAt.error()};
  const int nb = m.bind ? m.n_bound_params + m.n_bound_starts : 0;
  // Nothing changed: the compiled values are the bindings' values already.
  if (nb > 0 && !params.empty()) {
    std::vector<double> out(nb);
    std::vector<double> yp(m.start_yp, m.start_yp + m.n);
    for (int pass = 0; pass <= m.bind_passes; ++pass) {
      int rc = m.bind(t0, v.y.data(), yp.data(), v.p.data(), out.data());
      if (rc > 0) {
        int row = rc - 1;
        v.failure =
            row < m.n_bound_params
                ? fmt::format("the binding of parameter '{}' is outside its "
                              "domain",
                              m.param_names[m.bound_params[row]])
                : fmt::format(
                      "the start value of '{}' is outside its domain",
                      m.var_names[m.bound_starts[row - m.n_bound_params]]);
        return v;
      }
      if (rc != 0) {
        v.failure = "the parameter bindings could not be evaluated";
        return v;
      }
      if (pass == m.bind_passes)
        break;
      for (int j = 0; j < m.n_bound_params; ++j)
        if (!given[m.bound_params[j]])
          v.p[m.bound_params[j]] = out[j];
    }
    for (int j = 0; j < m.n_bound_starts; ++j)
      v.y[m.bound_starts[j]] = out[m.n_bound_params + j];
  }
  for (auto [i, value] : *startAt)
    v.y[i] = value;
  return v;
}

} // namespace ldae::runtime
