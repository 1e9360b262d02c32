// Checking a model's asserts (see Asserts.h).
#include "events/Asserts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <ostream>

namespace ldae::runtime {

namespace {

/// The values in the message known only at run time (the ABI's
/// assert_value_begin): n_asserts conditions come first.
size_t messageValueCount(const ldae_model &m) {
  if (m.n_asserts <= 0 || !m.assert_value_begin)
    return 0;
  return size_t(std::max(m.assert_value_begin[m.n_asserts], 0));
}

/// One value as String() shows it, by the placeholder's format.
std::string formatValue(double v, const std::string &format) {
  char buf[128];
  if (!format.empty() && format[0] == '%') {
    // The compiler checked it is one conversion of "feEgGdixXo".
    char conversion = format.back();
    if (std::string("dixXo").find(conversion) != std::string::npos) {
      std::string spec = format.substr(0, format.size() - 1) + "ll" + conversion;
      std::snprintf(buf, sizeof buf, spec.c_str(), static_cast<long long>(std::llround(v)));
    } else {
      std::snprintf(buf, sizeof buf, format.c_str(), v);
    }
    return buf;
  }
  int digits = 6, width = 0, left = 1;
  std::sscanf(format.c_str(), "g%d,%d,%d", &digits, &width, &left);
  if (std::fabs(v) < 1e15 && v == std::floor(v))
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
  else
    std::snprintf(buf, sizeof buf, "%.*g", std::clamp(digits, 1, 17), v);
  std::string text = buf;
  size_t w = size_t(std::clamp(width, 0, 1000));
  if (text.size() < w)
    text = left ? text + std::string(w - text.size(), ' ')
                : std::string(w - text.size(), ' ') + text;
  return text;
}

/// `message` with each placeholder "\x1f<k>:<format>\x1f" replaced by
/// values[k] formatted.
std::string fillMessage(const char *message, const double *values,
                        size_t count) {
  std::string in = message, out;
  size_t i = 0;
  while (i < in.size()) {
    size_t open = in.find('\x1f', i);
    size_t close = open == std::string::npos ? open : in.find('\x1f', open + 1);
    size_t colon = close == std::string::npos ? close : in.find(':', open);
    char *end = nullptr;
    unsigned long k = colon < close ? std::strtoul(in.c_str() + open + 1, &end, 10) : 0;
    if (colon >= close || end != in.c_str() + colon || k >= count) {
      out += in.substr(i);
      break;
    }
    out += in.substr(i, open - i);
    out += formatValue(values[k], in.substr(colon + 1, close - colon - 1));
    i = close + 1;
  }
  return out;
}

} // namespace

AssertChecker::AssertChecker(const ModelEval &ev, std::ostream *log)
    : ev_(ev), log_(log),
      holds_(size_t(std::max(ev.model().n_asserts, 0)) +
             messageValueCount(ev.model())),
      warned_(size_t(std::max(ev.model().n_asserts, 0)), false) {}

std::optional<std::string> AssertChecker::check(double t, const double *y,
                                                const double *yp) {
  const ldae_model &m = ev_.model();
  if (holds_.empty() || !m.asserts)
    return std::nullopt;
  if (m.asserts(t, y, yp, ev_.params(), holds_.data()) != 0)
    return fmt::format("the asserts could not be evaluated at t = {:.10g}", t);
  const size_t n = warned_.size();
  for (size_t i = 0; i < n; ++i) {
    if (holds_[i] != 0)
      continue;
    const char *msg = m.assert_message ? m.assert_message[i] : nullptr;
    const char *origin = m.assert_origin ? m.assert_origin[i] : nullptr;
    std::string text = "assert";
    if (msg && m.assert_value_begin) {
      int begin = m.assert_value_begin[i], end = m.assert_value_begin[i + 1];
      text = fillMessage(msg, holds_.data() + n + begin, size_t(end - begin));
    } else if (msg) {
      text = msg;
    }
    std::string what = fmt::format(
        "assertion failed at t = {:.10g}: {}{}", t, text,
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
