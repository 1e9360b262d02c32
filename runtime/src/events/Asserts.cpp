// Checking a model's asserts (see Asserts.h).
#include "events/Asserts.h"

#include <algorithm>
#include <fmt/format.h>
#include <ostream>

namespace ldae::runtime {

AssertChecker::AssertChecker(const ModelEval &ev, std::ostream *log)
    : ev_(ev), log_(log), holds_(std::max(ev.model().n_asserts, 0)),
      warned_(holds_.size(), false) {}

std::optional<std::string> AssertChecker::check(double t, const double *y,
                                                const double *yp) {
  const ldae_model &m = ev_.model();
  if (holds_.empty() || !m.asserts)
    return std::nullopt;
  if (m.asserts(t, y, yp, ev_.params(), holds_.data()) != 0)
    return fmt::format("the asserts could not be evaluated at t = {:.10g}", t);
  for (size_t i = 0; i < holds_.size(); ++i) {
    if (holds_[i] != 0)
      continue;
    const char *msg = m.assert_message ? m.assert_message[i] : nullptr;
    const char *origin = m.assert_origin ? m.assert_origin[i] : nullptr;
    std::string what = fmt::format(
        "assertion failed at t = {:.10g}: {}{}", t, msg ? msg : "assert",
        origin && *origin ? fmt::format(" (assert at {})", origin) : "");
    bool warning = m.assert_level && m.assert_level[i] == 1;
    if (!warning)
      return what;
    if (!warned_[i] && log_)
      *log_ << "warning: " << what << "\n";
    warned_[i] = true;
  }
  return std::nullopt;
}

} // namespace ldae::runtime
