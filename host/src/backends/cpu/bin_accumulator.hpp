#pragma once
// Sums per pose-bin key: open addressing with a well-mixed hash, made at most
// half full and grown at three quarters (a belief's table outgrows the caches
// and every lookup misses: a fuller table misses less often, and a key's next
// slots mostly share its cache line; paper3d's 64-session batch: 54 -> 57
// session-updates/s, 3.9 -> 2.7 GB). Used with 64-bit fixed-point vote mass (integer sums do not depend on
// the order of the votes, so the sorted read-out is the same for any
// schedule) and for the belief's fixed-point log-domain offsets.
#include <algorithm>
#include <bit>
#include <cassert>
#include <cstdint>
#include <span>
#include <vector>

#include "votes/bin_hash.hpp"

namespace sva {

// Which bits of the hash pick a key's home slot. A table filled in the slot order of another must not take its homes
// from the same bits as that one: a pair's terms reach its belief in the pair table's slot order, and with both on the
// low bits a belief smaller than the pair's table (just after forgetting) was swept once per size ratio while it grew,
// each sweep piling onto the last: up to 783 probes per addition, 21 on average (paper3d, a budget of 32,768). A
// copy into a table sized beforehand (growth, forgetting, the band's pruning) may share the bits: linear probing's
// total displacement does not depend on the order of insertion, only growing midway does. kSkip: a low-bits table
// starts that many bits up, for keys that share their lowest hash bits (one belief shard's, belief.hpp), which would
// otherwise all have their homes in one slot of 2^kSkip.
enum class HomeBits { low, high };

template <class Value, HomeBits kHome = HomeBits::low, unsigned kSkip = 0>
class BinTable {
 public:
  explicit BinTable(std::size_t expected = 1024) { init(expected); }

  void add(std::uint64_t key, Value v) { slot(key).value += v; }
  void set(std::uint64_t key, Value v) { slot(key).value = v; }
  // Adds v and returns the key's new value; *inserted tells whether the key was new.
  Value add_get(std::uint64_t key, Value v, bool* inserted) {
    const std::size_t before = size_;
    Value& x = slot(key).value;
    x += v;
    *inserted = size_ != before;
    return x;
  }
  // Whether the key is present; if so, *value is its value.
  bool find(std::uint64_t key, Value* value) const {
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      if (slots_[i].key == key) return *value = slots_[i].value, true;
      if (slots_[i].key == kEmpty) return false;
    }
  }
  // The value of a key, or Value{} when absent.
  Value get(std::uint64_t key) const {
    Value v{};
    find(key, &v);
    return v;
  }
  // The key in the slot a lookup of `key` reads first: one load, no probing (bench/speed/hash_floor.cpp times these as
  // the least an addition can cost).
  std::uint64_t home_key(std::uint64_t key) const { return slots_[home(key)].key; }
  // Loads the home slot of every key in [first, last) (key_of gives an element's key): independent loads, whose misses
  // overlap, so that additions or lookups of those keys right after find their slots in the cache (Belief::add says
  // why).
  template <class It, class KeyOf>
  void load_homes(It first, It last, KeyOf key_of) const {
    std::uint64_t seen = 0;
    for (; first != last; ++first) seen ^= home_key(key_of(*first));
    loaded_ ^= seen;  // kept, so that the loads are made
  }
  std::size_t size() const { return size_; }
  void clear() { init(1024); }
  // Empties the table but keeps its slots (a belief's reset: the next session reuses the allocation).
  void clear_keeping_capacity() {
    std::fill(slots_.begin(), slots_.end(), Slot{});
    size_ = 0;
    probes_ = 0;
  }
  std::size_t capacity() const { return slots_.size(); }
  // The slots a table made for `expected` keys has: at most half full.
  static std::size_t capacity_for(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected) cap *= 2;
    return cap;
  }
  std::size_t bytes() const { return slots_.size() * sizeof(Slot); }
  // Slots read by additions since the last clear (the first one each, and every step of a collision): the work
  // `sva bench` counts.
  std::uint64_t probes() const { return probes_; }
  // Slot arrays allocated by this table: at construction, clear() and every growth.
  std::size_t allocations() const { return allocations_; }
  // Visits every touched key in slot order (for order-independent reductions).
  template <class Fn>
  void for_each(Fn&& fn) const {
    for (const Slot& s : slots_)
      if (s.key != kEmpty) fn(s.key, s.value);
  }
  // Copies every key whose value is above zero, with its value, in slot order, into keys and values (each with room
  // for size() + 1 entries: a slot is written at the count so far, which never passes size()); returns how many.
  // Every slot is written and the position advanced by whether it is kept, without a branch: in a pair's table, a
  // fifth to a half full, a branch per slot went the wrong way at random, and its mispredictions were most of
  // Belief::terms' time.
  std::size_t copy_positive(std::uint64_t* keys, Value* values) const {
    std::size_t n = 0;
    for (const Slot& s : slots_) {
      keys[n] = s.key;
      values[n] = s.value;
      n += static_cast<std::size_t>(s.key != kEmpty) & static_cast<std::size_t>(s.value > Value{});
    }
    return n;
  }
  // Touched keys in increasing order with their values.
  void sorted(std::vector<std::uint64_t>* keys, std::vector<Value>* values) const {
    std::vector<Slot> touched;
    touched.reserve(size_);
    for (const Slot& s : slots_)
      if (s.key != kEmpty) touched.push_back(s);
    std::sort(touched.begin(), touched.end(), [](const Slot& a, const Slot& b) { return a.key < b.key; });
    keys->resize(touched.size());
    values->resize(touched.size());
    for (std::size_t j = 0; j < touched.size(); ++j) {
      (*keys)[j] = touched[j].key;
      (*values)[j] = touched[j].value;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = hash::kEmptyKey;
  // A key beside its value: a probe that finds its key has the value in the same cache line (the tables of a
  // pair's votes and of a belief outgrow the caches, and each lookup is a miss; two arrays made it two).
  struct Slot {
    std::uint64_t key = kEmpty;
    Value value{};
  };
  // The GPU tables' hash: one mixing function for every pose-bin table.
  std::size_t home(std::uint64_t key) const {
    const std::uint64_t h = hash::sva_hash64(key);
    return static_cast<std::size_t>(kHome == HomeBits::low ? (h >> kSkip) & mask_ : h >> shift_);
  }
  void init(std::size_t expected) {
    const std::size_t cap = capacity_for(expected);
    slots_.assign(cap, Slot{});
    set_mask(cap);
    size_ = 0;
    probes_ = 0;
    ++allocations_;
  }
  Slot& slot(std::uint64_t key) {
    assert(key != kEmpty);
    if ((size_ + 1) * 4 > slots_.size() * 3) grow();
    const std::size_t h = home(key);
    std::size_t i = h;
    while (slots_[i].key != key && slots_[i].key != kEmpty) i = (i + 1) & mask_;
    probes_ += ((i - h) & mask_) + 1;  // counted once, not per step: the loop stays free of a memory counter
    if (slots_[i].key == kEmpty) {
      slots_[i].key = key;
      ++size_;
    }
    return slots_[i];
  }
  void grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    set_mask(slots_.size());
    ++allocations_;
    for (const Slot& s : old) {
      if (s.key == kEmpty) continue;
      std::size_t i = home(s.key);
      while (slots_[i].key != kEmpty) i = (i + 1) & mask_;
      slots_[i] = s;
    }
  }
  void set_mask(std::size_t cap) {  // cap: a power of two
    mask_ = cap - 1;
    shift_ = 64 - static_cast<unsigned>(std::countr_zero(cap));
  }
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
  unsigned shift_ = 64;
  std::size_t allocations_ = 0;
  std::uint64_t probes_ = 0;
  mutable std::uint64_t loaded_ = 0;  // load_homes' keys, folded: nothing reads it
};

// Runs fn(item) for every item in order, a batch at a time, each batch's home slots in `table` loaded first
// (load_homes): for the additions or lookups of many keys in a table that outgrows the caches (Belief::add says why).
inline constexpr std::size_t kLoadBatch = 32;  // 16 and 8 measured slower on paper3d (docs/recognition.md)
template <class Table, class T, class KeyOf, class Fn>
void for_each_loaded(const Table& table, std::span<T> items, KeyOf key_of, Fn fn) {
  for (std::size_t i = 0; i < items.size(); i += kLoadBatch) {
    const std::span<T> batch = items.subspan(i, std::min(kLoadBatch, items.size() - i));
    table.load_homes(batch.begin(), batch.end(), key_of);
    for (T& item : batch) fn(item);
  }
}

// Fixed-point vote mass per bin.
using BinAccumulator = BinTable<std::int64_t>;
// A belief's fixed-point log-domain offsets per bin, filled from pair tables (BinAccumulator): the other bits.
using BeliefTable = BinTable<std::uint64_t, HomeBits::high>;

}  // namespace sva
