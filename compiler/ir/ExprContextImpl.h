// Private state of ExprContext shared by the files that implement its
// builders: the node arena, the uniquing table and per-node facts.
#pragma once

#include "ir/ExprContext.h"

#include <cassert>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

namespace ldae::ir {

/// Nested sums and products are flattened into their users only while they
/// have at most this many operands, so long chains that share prefixes stay
/// linear in size (see docs/ir.md).
constexpr unsigned kFlattenLimit = 8;

/// Users a node keeps in its own list before further users with it as
/// pivot go to the global uniquing table (ExprContext::intern).
constexpr unsigned kLocalUsers = 8;

/// True for finite integral doubles that are exact as integers.
inline bool isIntegral(double v) {
  return std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15;
}

/// Zero-filled memory straight from the kernel, for the node arena and the
/// uniquing table: no clearing pass and no copy when a table is replaced.
/// (Transparent huge pages were tried: zeroing 2 MiB pages on first touch
/// cost more than the TLB misses they saved.)
class HugeBlock {
public:
  HugeBlock() = default;
  explicit HugeBlock(size_t bytes);
  HugeBlock(HugeBlock &&o) noexcept : data_(o.data_), size_(o.size_) {
    o.data_ = nullptr;
    o.size_ = 0;
  }
  HugeBlock &operator=(HugeBlock &&o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
    return *this;
  }
  ~HugeBlock();
  char *get() const { return data_; }

private:
  char *data_ = nullptr;
  size_t size_ = 0;
};

/// A bump allocator: nodes and operand arrays live until the context dies.
class Arena {
public:
  void *allocate(size_t bytes, size_t align) {
    size_t offset = (used_ + align - 1) & ~(align - 1);
    if (blocks_.empty() || offset + bytes > blockSize_) {
      size_t size = bytes > kBlock ? bytes : kBlock;
      blocks_.emplace_back(size);
      blockSize_ = size;
      total_ += size;
      offset = 0;
    }
    used_ = offset + bytes;
    return blocks_.back().get() + offset;
  }
  size_t bytes() const { return total_; }

private:
  static constexpr size_t kBlock = 2 << 20;
  std::vector<HugeBlock> blocks_;
  size_t used_ = 0, blockSize_ = 0, total_ = 0;
};

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
    case ExprKind::External:
      if (a->externalId() != b->externalId() ||
          a->externalOutput() != b->externalOutput() ||
          a->constant() != b->constant())
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

/// The uniquing table: open addressing with linear probing. A slot is one
/// word, the node's address with the top 16 bits of its hash in the unused
/// high bits, so the table is small and a probe dereferences a node only
/// when the tag matches.
class NodeTable {
public:
  NodeTable() { resize(1024); }

  /// The node equal to `probe`, or null.
  ExprRef find(const Expr &probe) const {
    uint64_t tag = tagOf(probe.hash());
    for (size_t i = probe.hash() & mask_;; i = (i + 1) & mask_) {
      uint64_t s = slots_[i];
      if (!s)
        return nullptr;
      if ((s & kTagMask) == tag) {
        auto node = reinterpret_cast<ExprRef>(s & ~kTagMask);
        if (NodeEqual()(node, &probe))
          return node;
      }
    }
  }
  /// Adds `node`, known to be absent.
  void insert(ExprRef node) {
    if ((count_ + 1) * 10 > (mask_ + 1) * 6)
      grow();
    place(node);
    ++count_;
  }
  size_t bytes() const { return (mask_ + 1) * sizeof(uint64_t); }

private:
  static constexpr uint64_t kTagMask = 0xffffull << 48;
  HugeBlock memory_;
  uint64_t *slots_ = nullptr;
  size_t mask_ = 0, count_ = 0;

  static uint64_t tagOf(size_t hash) { return hash & kTagMask; }

  void resize(size_t n) {
    memory_ = HugeBlock(n * sizeof(uint64_t)); // zero: all slots empty
    slots_ = reinterpret_cast<uint64_t *>(memory_.get());
    mask_ = n - 1;
  }
  void place(ExprRef node) {
    auto bits = reinterpret_cast<uint64_t>(node);
    assert((bits & kTagMask) == 0 && "addresses above 2^48 are not expected");
    size_t i = node->hash() & mask_;
    while (slots_[i])
      i = (i + 1) & mask_;
    slots_[i] = bits | tagOf(node->hash());
  }
  void grow() {
    HugeBlock old = std::move(memory_);
    auto *oldSlots = reinterpret_cast<uint64_t *>(old.get());
    size_t oldSize = mask_ + 1;
    resize(oldSize * 2);
    for (size_t i = 0; i < oldSize; ++i)
      if (oldSlots[i])
        place(reinterpret_cast<ExprRef>(oldSlots[i] & ~kTagMask));
  }
};

struct ExprContext::Impl {
  Arena arena;
  NodeTable table;
  uint32_t count = 0; // nodes made: the next id
  ExprRef time = nullptr;
  ExprRef zero = nullptr, one = nullptr, minusOne = nullptr;
};

} // namespace ldae::ir
