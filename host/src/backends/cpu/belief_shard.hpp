#pragma once
// One shard of the CPU reference belief (backends/cpu/belief.hpp): the offsets of the bins whose hash falls in it, in
// an open-addressing table in host memory, with the estimate's reductions over those bins kept current as it folds.
// A belief is split into shards so that one session's pairs add their terms on every core at once, each shard by one
// worker (issue 52: one table under one lock stopped the CPU reference scaling past 8 threads, where the additions,
// 14% of the work at 100 paper3d readings, became the critical path).
#include <cstdint>
#include <span>
#include <vector>

#include "backends/cpu/bin_accumulator.hpp"
#include "belief/belief_state.hpp"

namespace sva {

class BeliefShard {
 public:
  BeliefShard(std::uint32_t objects, std::uint32_t mass_bits, std::size_t expected);

  void reset();
  // Adds `count` times each term's offset (integers: the order of terms and of pairs does not matter).
  void add(std::span<const BinOffset> terms, std::uint32_t count);
  // Forgets every bin below `below` except those in `keep` (sorted keys of this shard). Returns how many it forgot.
  std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep);

  std::uint64_t max_offset() const { return max_; }
  const std::vector<std::uint64_t>& touched_per_object() const { return touched_; }
  const std::vector<std::uint64_t>& best_offset() const { return best_offset_; }
  const std::vector<std::uint64_t>& best_key() const { return best_key_; }
  // Adds each object's sva_exp2_neg_units(max - offset, mass_bits) over this shard's bins within the band of the
  // belief's maximum `max` (every bin whose weight is not 0 lies in this shard's band: its own maximum is not larger).
  void add_band_mass(std::uint64_t max, std::vector<std::uint64_t>* mass) const;
  // This shard's exact top min(n, bins in its band), best first, from its band alone (cheap: no pass over the table).
  std::vector<BinOffset> band_top(std::size_t n) const;
  // This shard's exact top k (or every bin, if it has fewer), best first: from its band when the band holds k bins,
  // else from a pass over its table (or the upper set a pass left).
  std::vector<BinOffset> top(std::size_t k) const;

  std::uint64_t get(std::uint64_t key) const { return offset_.get(key); }
  std::uint64_t home_key(std::uint64_t key) const { return offset_.home_key(key); }
  template <class Fn>
  void for_each(Fn&& fn) const {
    offset_.for_each(fn);
  }
  std::size_t size() const { return offset_.size(); }
  std::size_t bytes() const { return offset_.bytes() + band_.bytes() + upper_.bytes(); }
  std::size_t allocations() const { return retired_allocations_ + offset_.allocations(); }
  std::uint64_t probes() const { return offset_.probes(); }

 private:
  // Offsets only grow, so additions keep the estimate's reductions up to date (DESIGN's "no pass over every bin per
  // estimate"): the maximum, each object's touched count and best bin directly, and the object masses and top-k
  // through the *band*: the bins within band_width_ of the maximum, the only ones whose weight 2^(offset - M) at
  // mass_bits is not 0. A bin leaves the band only as the maximum grows, so the band set holds every bin in the band
  // (and some stale ones, skipped when read, pruned as it grows), each with its offset, so that reading the band
  // never looks a bin up in the (much larger) offset table.
  bool in_band(std::uint64_t offset, std::uint64_t max) const { return max - offset < band_width_; }
  void add_term(const BinOffset& t, std::uint32_t count);
  void note(std::uint64_t key, std::uint64_t offset, bool inserted);
  void prune_band();
  void recount();
  // The best bins past the band without a pass over the table each time: upper_ holds the key of every bin whose
  // offset is at least upper_floor_ (offsets only grow, so a bin that enters never leaves, and add() sees every bin
  // that crosses the floor; its offset is read from the table when asked); every other bin lies below the floor. Set
  // by a pass over the table for 4 times the bins asked, cut back to its own best 4k when it has grown eightfold,
  // dropped when bins are forgotten and on reset (upper_floor_ 0: none kept, the next request past the band makes it
  // again).
  std::vector<BinOffset> best_past_band(std::size_t k) const;
  std::vector<BinOffset> upper_best(std::size_t n) const;  // the upper set's best n, best first
  // Makes the upper set from `best`, a best-first top `wide` of bins that holds every bin of the table above its last
  // one; none when it has fewer than `wide`.
  void keep_upper(const std::vector<BinOffset>& best, std::size_t wide) const;
  void drop_upper() const;

  std::uint32_t mass_bits_;
  std::uint64_t band_width_;
  BeliefTable offset_;
  std::size_t retired_allocations_ = 0;  // of offset tables replaced by forget_below
  std::uint64_t max_ = 0;
  std::vector<std::uint64_t> touched_, best_offset_, best_key_;
  BeliefTable band_;  // each band bin's offset as of its last addition (current while it is in the band)
  std::size_t band_pruned_size_ = 0;
  std::uint64_t band_pruned_max_ = 0;      // max_ at the last prune
  mutable BeliefTable upper_{4};           // best_past_band's bins (read and made under the belief's kept-best lock)
  mutable std::uint64_t upper_floor_ = 0;  // 0: upper_ is not kept
  mutable std::size_t upper_made_size_ = 0;
};

// The best bins first: larger offsets, ties to the smaller key.
inline bool better_bin(const BinOffset& a, const BinOffset& b) {
  return a.offset != b.offset ? a.offset > b.offset : a.key < b.key;
}

}  // namespace sva
