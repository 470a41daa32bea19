#pragma once
// Sums per pose-bin key: open addressing with a well-mixed hash, grown at half
// load. Used with 64-bit fixed-point vote mass (integer sums do not depend on
// the order of the votes, so the sorted read-out is the same for any
// schedule) and for the belief's fixed-point log-domain offsets.
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include "core/hash.hpp"

namespace sva {

template <class Value>
class BinTable {
 public:
  explicit BinTable(std::size_t expected = 1024) { init(expected); }

  void add(std::uint64_t key, Value v) { slot(key) += v; }
  void set(std::uint64_t key, Value v) { slot(key) = v; }
  // Adds v and returns the key's new value; *inserted tells whether the key was new.
  Value add_get(std::uint64_t key, Value v, bool* inserted) {
    const std::size_t before = size_;
    Value& x = slot(key);
    x += v;
    *inserted = size_ != before;
    return x;
  }
  // The value of a key, or Value{} when absent.
  Value get(std::uint64_t key) const {
    std::size_t i = mix(key) & mask_;
    for (;;) {
      if (keys_[i] == key) return values_[i];
      if (keys_[i] == kEmpty) return Value{};
      i = (i + 1) & mask_;
    }
  }
  std::size_t size() const { return size_; }
  void clear() { init(1024); }
  // Empties the table but keeps its slots (a belief's reset: the next session reuses the allocation).
  void clear_keeping_capacity() {
    std::fill(keys_.begin(), keys_.end(), kEmpty);
    std::fill(values_.begin(), values_.end(), Value{});
    size_ = 0;
  }
  std::size_t capacity() const { return keys_.size(); }
  // Slot arrays allocated by this table: at construction, clear() and every growth.
  std::size_t allocations() const { return allocations_; }
  // Visits every touched key in slot order (for order-independent reductions).
  template <class Fn>
  void for_each(Fn&& fn) const {
    for (std::size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] != kEmpty) fn(keys_[i], values_[i]);
  }
  // Touched keys in increasing order with their values.
  void sorted(std::vector<std::uint64_t>* keys, std::vector<Value>* values) const {
    std::vector<std::uint64_t> k;
    k.reserve(size_);
    for (std::uint64_t key : keys_)
      if (key != kEmpty) k.push_back(key);
    std::sort(k.begin(), k.end());
    values->resize(k.size());
    for (std::size_t j = 0; j < k.size(); ++j) (*values)[j] = get(k[j]);
    *keys = std::move(k);
  }

 private:
  static constexpr std::uint64_t kEmpty = hash::kEmptyKey;
  // The GPU tables' hash: one mixing function for every pose-bin table.
  static std::uint64_t mix(std::uint64_t x) { return hash::sva_hash64(x); }
  void init(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected) cap *= 2;
    keys_.assign(cap, kEmpty);
    values_.assign(cap, Value{});
    mask_ = cap - 1;
    size_ = 0;
    ++allocations_;
  }
  Value& slot(std::uint64_t key) {
    assert(key != kEmpty);
    if ((size_ + 1) * 2 > keys_.size()) grow();
    std::size_t i = mix(key) & mask_;
    for (;;) {
      if (keys_[i] == key) return values_[i];
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        ++size_;
        return values_[i];
      }
      i = (i + 1) & mask_;
    }
  }
  void grow() {
    std::vector<std::uint64_t> old_keys(keys_.size() * 2, kEmpty);
    std::vector<Value> old_values(keys_.size() * 2, Value{});
    old_keys.swap(keys_);
    old_values.swap(values_);
    mask_ = keys_.size() - 1;
    ++allocations_;
    for (std::size_t j = 0; j < old_keys.size(); ++j) {
      if (old_keys[j] == kEmpty) continue;
      std::size_t i = mix(old_keys[j]) & mask_;
      while (keys_[i] != kEmpty) i = (i + 1) & mask_;
      keys_[i] = old_keys[j];
      values_[i] = old_values[j];
    }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<Value> values_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
  std::size_t allocations_ = 0;
};

// Fixed-point vote mass per bin.
using BinAccumulator = BinTable<std::int64_t>;

}  // namespace sva
