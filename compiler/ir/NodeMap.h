// Hash maps and sets keyed by expression nodes (through their creation ids),
// for the memo tables of DAG algorithms. Ids are grouped in blocks of 64: a
// small hash table finds a block's dense chunk, so nodes built together
// (consecutive ids) share a chunk and a cache line, a ten-node expression
// costs a few chunks, and a million-node DAG stays cache-friendly. Never
// keyed by address.
#pragma once

#include "ir/Expr.h"

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace ldae::ir {

namespace detail {

/// Maps a block number (id / 64) to a dense index 0, 1, 2... in insertion
/// order: open addressing, remembering the last block for sequential runs.
class BlockIndex {
public:
  static constexpr uint32_t kNone = UINT32_MAX;

  uint32_t find(uint32_t block) const {
    if (block == lastBlock_)
      return lastIndex_;
    if (keys_.empty())
      return kNone;
    for (size_t i = slot(block);; i = (i + 1) & mask_) {
      if (keys_[i] == block) {
        lastBlock_ = block;
        lastIndex_ = values_[i];
        return lastIndex_;
      }
      if (keys_[i] == kNone)
        return kNone;
    }
  }
  /// The index of `block`, adding it (as `count()`) if absent.
  uint32_t insert(uint32_t block) {
    if (uint32_t found = find(block); found != kNone)
      return found;
    if ((count_ + 1) * 2 > keys_.size())
      grow();
    size_t i = slot(block);
    while (keys_[i] != kNone)
      i = (i + 1) & mask_;
    keys_[i] = block;
    values_[i] = count_;
    lastBlock_ = block;
    lastIndex_ = count_;
    return count_++;
  }
  uint32_t count() const { return count_; }
  void clear() { *this = BlockIndex(); }

private:
  std::vector<uint32_t> keys_, values_;
  size_t mask_ = 0;
  uint32_t count_ = 0;
  mutable uint32_t lastBlock_ = kNone, lastIndex_ = kNone;

  size_t slot(uint32_t block) const {
    return (block * 0x9e3779b97f4a7c15ull >> 20) & mask_;
  }
  void grow() {
    std::vector<uint32_t> oldKeys(keys_.empty() ? 8 : keys_.size() * 2, kNone);
    std::vector<uint32_t> oldValues(oldKeys.size());
    oldKeys.swap(keys_);
    oldValues.swap(values_);
    mask_ = keys_.size() - 1;
    for (size_t j = 0; j < oldKeys.size(); ++j) {
      if (oldKeys[j] == kNone)
        continue;
      size_t i = slot(oldKeys[j]);
      while (keys_[i] != kNone)
        i = (i + 1) & mask_;
      keys_[i] = oldKeys[j];
      values_[i] = oldValues[j];
    }
  }
};

} // namespace detail

template <typename V> class NodeMap {
public:
  /// The value stored for `e`, or null.
  V *find(ExprRef e) {
    uint32_t c = blocks_.find(e->id() >> 6);
    if (c == detail::BlockIndex::kNone)
      return nullptr;
    Chunk &chunk = *chunks_[c];
    uint64_t bit = uint64_t(1) << (e->id() & 63);
    return chunk.present & bit ? &chunk.values[e->id() & 63] : nullptr;
  }
  const V *find(ExprRef e) const {
    return const_cast<NodeMap *>(this)->find(e);
  }
  bool contains(ExprRef e) const { return find(e) != nullptr; }

  /// Stores `v` for `e` unless `e` has a value; returns the stored value and
  /// whether it was inserted.
  std::pair<V *, bool> insert(ExprRef e, V v) {
    uint32_t c = blocks_.insert(e->id() >> 6);
    if (c == chunks_.size())
      chunks_.push_back(std::make_unique<Chunk>());
    Chunk &chunk = *chunks_[c];
    uint64_t bit = uint64_t(1) << (e->id() & 63);
    V *slot = &chunk.values[e->id() & 63];
    if (chunk.present & bit)
      return {slot, false};
    chunk.present |= bit;
    *slot = std::move(v);
    ++count_;
    return {slot, true};
  }
  /// Stores `v` for `e`, replacing any value.
  void set(ExprRef e, V v) {
    auto [slot, inserted] = insert(e, v);
    if (!inserted)
      *slot = std::move(v);
  }
  size_t size() const { return count_; }
  void clear() {
    blocks_.clear();
    chunks_.clear();
    count_ = 0;
  }

private:
  struct Chunk {
    uint64_t present = 0;
    V values[64];
  };
  detail::BlockIndex blocks_;
  std::vector<std::unique_ptr<Chunk>> chunks_;
  size_t count_ = 0;
};

/// A set of nodes: one 64-bit mask per block of ids.
class NodeSet {
public:
  /// Inserts `e`; false if it was already there.
  bool insert(ExprRef e) {
    uint32_t c = blocks_.insert(e->id() >> 6);
    if (c == masks_.size())
      masks_.push_back(0);
    uint64_t bit = uint64_t(1) << (e->id() & 63);
    if (masks_[c] & bit)
      return false;
    masks_[c] |= bit;
    return true;
  }
  bool contains(ExprRef e) const {
    uint32_t c = blocks_.find(e->id() >> 6);
    return c != detail::BlockIndex::kNone && (masks_[c] >> (e->id() & 63) & 1);
  }

private:
  detail::BlockIndex blocks_;
  std::vector<uint64_t> masks_;
};

} // namespace ldae::ir
