// The kinds of the driver's failures; see ErrorKind.h.
#include "ErrorKind.h"

#include "ldae/Rebind.h"

#include <string>

namespace ldae::driver {

namespace {

int indexOf(const char *const *names, int n, const std::string &name) {
  for (int i = 0; i < n; ++i)
    if (names && names[i] && name == names[i])
      return i;
  return -1;
}

} // namespace

int exitCode(ErrorKind kind) {
  switch (kind) {
  case ErrorKind::ModelError:
    return 1;
  case ErrorKind::BadOption:
  case ErrorKind::NeedsRecompile:
    return 2;
  case ErrorKind::NumericalFailure:
    return 3;
  }
  return 1;
}

ErrorKind errorKindOfExitCode(int code) {
  switch (code) {
  case 2:
    return ErrorKind::BadOption;
  case 3:
    return ErrorKind::NumericalFailure;
  default:
    return ErrorKind::ModelError;
  }
}

const char *errorKindName(ErrorKind kind) {
  switch (kind) {
  case ErrorKind::ModelError:
    return "model-error";
  case ErrorKind::BadOption:
    return "bad-option";
  case ErrorKind::NeedsRecompile:
    return "needs-recompile";
  case ErrorKind::NumericalFailure:
    return "numerical-failure";
  }
  return "model-error";
}

bool needsRecompile(const ldae_model &m, const RunRequest &run) {
  for (const auto &[name, value] : run.params) {
    int k = indexOf(m.param_names, m.n_params, name);
    if (k < 0)
      return false; // an unknown name: no compile gives it
    if (m.param_structural && m.param_structural[k])
      return m.param_structural[k] != runtime::kConstantParameter;
  }
  for (const auto &[name, value] : run.starts) {
    if (indexOf(m.var_names, m.n, name) >= 0)
      continue;
    // Reported but no unknown: solved out or an alias.
    return indexOf(m.output_names, m.n_outputs, name) >= 0;
  }
  return false;
}

} // namespace ldae::driver
