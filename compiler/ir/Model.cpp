// Model bookkeeping: adding and finding variables and parameters by name,
// and the user's spelling of variables and their derivatives.
#include "ir/Model.h"
#include "ir/Query.h"

#include <cassert>

namespace ldae::ir {

const char *stateSelectName(StateSelect s) {
  switch (s) {
  case StateSelect::Never:
    return "never";
  case StateSelect::Avoid:
    return "avoid";
  case StateSelect::Default:
    return "default";
  case StateSelect::Prefer:
    return "prefer";
  case StateSelect::Always:
    return "always";
  }
  assert(false && "unknown state selection");
  return "default";
}

VarId Model::addVariable(Variable v) {
  auto id = static_cast<VarId>(variables.size());
  variables.push_back(std::move(v));
  return id;
}

ParamId Model::addParameter(Parameter p) {
  auto id = static_cast<ParamId>(parameters.size());
  parameters.push_back(std::move(p));
  return id;
}

std::optional<VarId> Model::findVariable(const std::string &name) const {
  // The first declaration keeps the name.
  for (; varsIndexed_ < variables.size(); ++varsIndexed_)
    varIndex_.emplace(variables[varsIndexed_].name,
                      static_cast<VarId>(varsIndexed_));
  auto it = varIndex_.find(name);
  if (it == varIndex_.end())
    return std::nullopt;
  return it->second;
}

std::optional<ParamId> Model::findParameter(const std::string &name) const {
  for (; paramsIndexed_ < parameters.size(); ++paramsIndexed_)
    paramIndex_.emplace(parameters[paramsIndexed_].name,
                        static_cast<ParamId>(paramsIndexed_));
  auto it = paramIndex_.find(name);
  if (it == paramIndex_.end())
    return std::nullopt;
  return it->second;
}

std::vector<double> Model::parameterValues() const {
  std::vector<double> values;
  values.reserve(parameters.size());
  for (const Parameter &p : parameters)
    values.push_back(p.value);
  return values;
}

size_t Model::userParameterCount() const {
  size_t n = parameters.size();
  while (n > 0 && parameters[n - 1].discrete)
    --n;
  return n;
}

std::vector<bool> Model::structuralParameters() const {
  std::vector<bool> structural(parameters.size(), false);
  std::vector<ParamId> work;
  for (ParamId p = 0; p < parameters.size(); ++p)
    if (parameters[p].structural) {
      structural[p] = true;
      work.push_back(p);
    }
  while (!work.empty()) {
    ParamId p = work.back();
    work.pop_back();
    if (ExprRef b = parameters[p].binding)
      for (ParamId q : freeParameters(b))
        if (q < parameters.size() && !structural[q]) {
          structural[q] = true;
          work.push_back(q);
        }
  }
  return structural;
}

bool Model::verbatimVariable(VarId v) const {
  return v < variables.size() && variables[v].input != EventInput::None;
}

bool Model::verbatimParameter(ParamId p) const {
  return p < parameters.size() && parameters[p].discrete;
}

std::string Model::variableName(VarKey key) const {
  std::string name = variableName(key.var);
  for (unsigned k = 0; k < key.order; ++k)
    name = "der(" + name + ")";
  return name;
}

std::string Model::variableName(VarId v) const {
  assert(v < variables.size() && "unknown variable");
  return v < variables.size() ? variables[v].name : "v" + std::to_string(v);
}

std::string Model::parameterName(ParamId p) const {
  assert(p < parameters.size() && "unknown parameter");
  return p < parameters.size() ? parameters[p].name : "p" + std::to_string(p);
}

} // namespace ldae::ir
