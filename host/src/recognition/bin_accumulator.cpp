#include "recognition/bin_accumulator.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace sva {

namespace {
std::uint64_t mix(std::uint64_t x) {
  x ^= x >> 31;
  x *= 0x7fb5d329728ea185ull;
  x ^= x >> 27;
  x *= 0x81dadef4bc2dd44dull;
  x ^= x >> 33;
  return x;
}
}  // namespace

BinAccumulator::BinAccumulator(std::size_t expected) {
  std::size_t cap = 16;
  while (cap < 2 * expected) cap *= 2;
  keys_.assign(cap, kEmpty);
  mass_.assign(cap, 0);
  mask_ = cap - 1;
}

void BinAccumulator::clear() {
  std::fill(keys_.begin(), keys_.end(), kEmpty);
  std::fill(mass_.begin(), mass_.end(), 0);
  size_ = 0;
}

void BinAccumulator::add(std::uint64_t key, std::int64_t mass) {
  assert(key != kEmpty);
  std::size_t i = mix(key) & mask_;
  for (;;) {
    if (keys_[i] == key) {
      mass_[i] += mass;
      return;
    }
    if (keys_[i] == kEmpty) {
      keys_[i] = key;
      mass_[i] = mass;
      if (++size_ * 2 > keys_.size()) grow();
      return;
    }
    i = (i + 1) & mask_;
  }
}

void BinAccumulator::grow() {
  std::vector<std::uint64_t> old_keys;
  std::vector<std::int64_t> old_mass;
  old_keys.swap(keys_);
  old_mass.swap(mass_);
  keys_.assign(old_keys.size() * 2, kEmpty);
  mass_.assign(old_keys.size() * 2, 0);
  mask_ = keys_.size() - 1;
  for (std::size_t j = 0; j < old_keys.size(); ++j) {
    if (old_keys[j] == kEmpty) continue;
    std::size_t i = mix(old_keys[j]) & mask_;
    while (keys_[i] != kEmpty) i = (i + 1) & mask_;
    keys_[i] = old_keys[j];
    mass_[i] = old_mass[j];
  }
}

void BinAccumulator::sorted(std::vector<std::uint64_t>* keys, std::vector<std::int64_t>* mass) const {
  std::vector<std::size_t> slots;
  slots.reserve(size_);
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] != kEmpty) slots.push_back(i);
  std::sort(slots.begin(), slots.end(), [&](std::size_t a, std::size_t b) { return keys_[a] < keys_[b]; });
  keys->resize(slots.size());
  mass->resize(slots.size());
  for (std::size_t k = 0; k < slots.size(); ++k) {
    (*keys)[k] = keys_[slots[k]];
    (*mass)[k] = mass_[slots[k]];
  }
}

}  // namespace sva
