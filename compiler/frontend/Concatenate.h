// Array concatenation (MLS 10.4.2): cat(k, A, B, ...) and the matrix
// constructor [a, b; c, d], which is cat(1, cat(2, a, b), cat(2, c, d))
// after promoting every element to at least two dimensions.
#pragma once

#include "frontend/Value.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ldae::frontend {

/// `v` with trailing dimensions of size 1 up to `ndims` dimensions.
Value promote(Value v, size_t ndims);

/// The parts joined along dimension `axis` (0-based). The parts must have
/// the same number of dimensions and agree in every other one; otherwise
/// nothing, with `mismatch` the two shapes that differ.
std::optional<Value>
concatenate(const std::vector<Value> &parts, size_t axis,
            std::pair<std::string, std::string> &mismatch);

} // namespace ldae::frontend
