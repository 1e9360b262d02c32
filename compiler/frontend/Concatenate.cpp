#include "frontend/Concatenate.h"

namespace ldae::frontend {

Value promote(Value v, size_t ndims) {
  while (v.shape.size() < ndims)
    v.shape.push_back(1);
  return v;
}

std::optional<Value>
concatenate(const std::vector<Value> &parts, size_t axis,
            std::pair<std::string, std::string> &mismatch) {
  const std::vector<int64_t> &first = parts.at(0).shape;
  Value out;
  out.shape = first;
  out.shape[axis] = 0;
  for (const Value &p : parts) {
    bool agree = p.shape.size() == first.size();
    for (size_t k = 0; agree && k < first.size(); ++k)
      agree = k == axis || p.shape[k] == first[k];
    if (!agree) {
      mismatch = {describeShape(first), describeShape(p.shape)};
      return std::nullopt;
    }
    out.shape[axis] += p.shape[axis];
  }
  // Row-major: for each index before the axis, each part's slab in turn.
  int64_t outer = 1;
  for (size_t k = 0; k < axis; ++k)
    outer *= first[k];
  size_t total = 0;
  for (const Value &p : parts)
    total += p.elems.size();
  out.elems.reserve(total);
  for (int64_t o = 0; o < outer; ++o)
    for (const Value &p : parts) {
      size_t slab = outer ? p.elems.size() / static_cast<size_t>(outer) : 0;
      auto begin = p.elems.begin() + static_cast<std::ptrdiff_t>(o * slab);
      out.elems.insert(out.elems.end(), begin,
                       begin + static_cast<std::ptrdiff_t>(slab));
    }
  return out;
}

} // namespace ldae::frontend
