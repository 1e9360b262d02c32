// assert(condition, message, level) of a model (ldae_model::asserts),
// checked at every output row and event: an error stops the run (status 3,
// the message and where the assert is written), a warning is reported
// once on the log (docs/events.md).
#pragma once

#include "model/ModelEval.h"

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace ldae::runtime {

class AssertChecker {
public:
  AssertChecker(const ModelEval &ev, std::ostream *log);

  /// The failure message of the first error-level assert that does not
  /// hold at (t, y, y'), or nothing; warns about the others once.
  std::optional<std::string> check(double t, const double *y, const double *yp);

private:
  const ModelEval &ev_;
  std::ostream *log_;
  std::vector<double> holds_;
  std::vector<bool> warned_;
};

} // namespace ldae::runtime
