// Private state of ExprContext shared by the files that implement its
// builders: the node arena, the uniquing table and per-node facts.
#pragma once

#include "ir/ExprContext.h"

#include <cmath>
#include <cstring>
#include <memory>
#include <unordered_set>
#include <vector>

namespace ldae::ir {

/// Nested sums and products are flattened into their users only while they
/// have at most this many operands, so long chains that share prefixes stay
/// linear in size (see docs/ir.md).
constexpr unsigned kFlattenLimit = 8;

/// True for finite integral doubles that are exact as integers.
inline bool isIntegral(double v) {
  return std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15;
}

/// A bump allocator: nodes and operand arrays live until the context dies.
class Arena {
public:
  void *allocate(size_t bytes, size_t align) {
    size_t offset = (used_ + align - 1) & ~(align - 1);
    if (blocks_.empty() || offset + bytes > blockSize_) {
      size_t size = bytes > kBlock ? bytes : kBlock;
      blocks_.push_back(std::make_unique<char[]>(size));
      blockSize_ = size;
      total_ += size;
      offset = 0;
    }
    used_ = offset + bytes;
    return blocks_.back().get() + offset;
  }
  size_t bytes() const { return total_; }

private:
  static constexpr size_t kBlock = 1 << 20;
  std::vector<std::unique_ptr<char[]>> blocks_;
  size_t used_ = 0, blockSize_ = 0, total_ = 0;
};

struct NodeHash {
  size_t operator()(ExprRef e) const { return e->hash(); }
};

/// Structural equality of nodes whose operands are already uniqued.
struct NodeEqual {
  bool operator()(ExprRef a, ExprRef b) const {
    if (a->hash() != b->hash() || a->kind() != b->kind() ||
        a->numOperands() != b->numOperands())
      return false;
    switch (a->kind()) {
    case ExprKind::Constant: {
      double x = a->constant(), y = b->constant();
      return std::memcmp(&x, &y, sizeof x) == 0;
    }
    case ExprKind::Parameter:
    case ExprKind::Pre:
      return a->var() == b->var();
    case ExprKind::Variable:
      return a->var() == b->var() && a->order() == b->order();
    case ExprKind::Call:
      if (a->func() != b->func())
        return false;
      break;
    case ExprKind::Compare:
      if (a->compare() != b->compare())
        return false;
      break;
    default:
      break;
    }
    for (unsigned i = 0; i < a->numOperands(); ++i)
      if (a->operand(i) != b->operand(i))
        return false;
    return true;
  }
};

struct ExprContext::Impl {
  Arena arena;
  std::unordered_set<ExprRef, NodeHash, NodeEqual> table;
  std::vector<ExprRef> nodes;     // by id
  std::vector<uint8_t> total;     // by id: ExprContext::isTotal
  ExprRef time = nullptr;
};

} // namespace ldae::ir
