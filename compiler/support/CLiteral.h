// A double as C source text, for the C that ldaec writes (emitted models,
// compiled Modelica functions): exact to the bit, and of type double even
// when integral (`1.0`, never `1`, so `1/2` stays a division of doubles).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace ldae {

inline std::string cDoubleLiteral(double v) {
  if (std::isnan(v))
    return "NAN";
  if (std::isinf(v))
    return v > 0 ? "HUGE_VAL" : "(-HUGE_VAL)";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".en") == std::string::npos)
    s += ".0";
  return v < 0 ? "(" + s + ")" : s;
}

} // namespace ldae
