// The value of an lsd expression during flattening: a scalar or an array
// (any rank, row-major) of IR expressions, or a string (attributes such as
// `unit` take strings).
#pragma once

#include "ir/Expr.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace ldae::frontend {

struct Value {
  std::vector<int64_t> shape; // empty: scalar
  std::vector<ir::ExprRef> elems;
  bool isString = false;
  std::string str;

  static Value scalar(ir::ExprRef e) {
    Value v;
    v.elems.push_back(e);
    return v;
  }
  static Value string(std::string s) {
    Value v;
    v.isString = true;
    v.str = std::move(s);
    return v;
  }
  bool isScalar() const { return shape.empty() && !isString; }
  ir::ExprRef scalarExpr() const { return elems.empty() ? nullptr : elems[0]; }
  size_t size() const { return elems.size(); }
  /// Element `i` along the first dimension (0-based): a row of a matrix.
  Value row(int64_t i) const {
    Value v;
    v.shape.assign(shape.begin() + 1, shape.end());
    size_t n = shape.empty() || shape[0] == 0 ? 0 : elems.size() / shape[0];
    v.elems.assign(elems.begin() + i * n, elems.begin() + (i + 1) * n);
    return v;
  }
};

/// A number that should be an integer, as messages show it.
inline std::string fmtInteger(double v) {
  // The range test comes first: converting nan or inf is undefined.
  if (v > -1e15 && v < 1e15 &&
      v == static_cast<double>(static_cast<long long>(v)))
    return std::to_string(static_cast<long long>(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

/// "scalar", "array of 3", "3x2 array" for messages.
inline std::string describeShape(const std::vector<int64_t> &shape) {
  if (shape.empty())
    return "a scalar";
  std::string s;
  for (size_t i = 0; i < shape.size(); ++i)
    s += (i ? "x" : "") + std::to_string(shape[i]);
  return "an array of size " + s;
}

} // namespace ldae::frontend
