#pragma once
// The CPU reference belief (belief/belief_state.hpp says what a belief is): the offsets in an open-addressing table
// in host memory, folded pair by pair.
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "backends/cpu/bin_accumulator.hpp"
#include "belief/belief_state.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct PairVotes;

// The CPU reference belief.
class Belief final : public BeliefState {
 public:
  Belief(const PoseSpace& space, double eps);

  // Multiplies in one pair factor `count` times (count 2: both orders of Eq 5,
  // which cast the same votes). A pair with no vote mass leaves the belief
  // unchanged (it carries no information about the pose). Returns whether it folded.
  bool fold(const PairVotes& votes, std::uint32_t count = 1);
  // The same in two steps: the pair's per-bin offset increments, which only
  // read the belief's eps (pairs compute theirs in parallel), then their
  // addition (integers: the order of pairs does not matter).
  std::vector<BinOffset> terms(const BinAccumulator& votes) const;
  void terms(const BinAccumulator& votes, std::vector<BinOffset>* out) const;  // into *out, its capacity reused
  bool add(const std::vector<BinOffset>& terms, std::uint32_t count);

  void reset() override;
  std::size_t table_allocations() const override { return retired_allocations_ + offset_.allocations(); }
  std::size_t pairs_folded() const override { return pairs_; }
  std::size_t touched() const override { return offset_.size(); }
  std::size_t table_bytes() const override { return offset_.bytes() + band_.bytes() + upper_.bytes(); }
  BeliefSummary summarise() const override;
  std::vector<BinOffset> best_bins(std::size_t k) const override;
  std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const override;
  std::vector<BinOffset> table() const override;
  std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) override;

  std::uint64_t offset(std::uint64_t key) const { return offset_.get(key); }
  // Slots of the offset table probed by additions since it was last made or emptied (the work `sva bench` counts).
  std::uint64_t table_probes() const { return offset_.probes(); }

 private:
  // Offsets only grow, so the fold keeps the estimate's reductions up to date
  // (DESIGN's "no pass over every bin per estimate"): the maximum, each
  // object's touched count and best bin directly, and the object masses and
  // top-k through the *band*: the bins within band_width_ of the maximum, the
  // only ones whose weight 2^(offset - M) at mass_bits is not 0. A bin leaves
  // the band only as the maximum grows, so the band set holds every bin in
  // the band (and some stale ones, skipped when read, pruned as it grows),
  // each with its offset, so that reading the band never looks a bin up in
  // the (much larger) offset table.
  bool in_band(std::uint64_t offset) const { return max_ - offset < band_width_; }
  void add_term(const BinOffset& t, std::uint32_t count);  // one term of add(), its reductions kept current
  void note(std::uint64_t key, std::uint64_t offset, bool inserted);
  void forget_best();  // the belief changed: best_bins' kept answer is stale
  void prune_band();
  // The best bins past the band (best_bins) without a pass over the table each time: upper_ holds the key of every
  // bin whose offset is at least upper_floor_ (offsets only grow, so a bin that enters never leaves, and add() sees
  // every bin that crosses the floor; its offset is read from the table when asked); every other bin lies below the
  // floor. Set by a pass over the table for 4 times the bins asked, dropped when it has grown eightfold, when bins
  // are forgotten and on reset (upper_floor_ 0: none kept, the next request past the band makes it again).
  std::vector<BinOffset> best_past_band(std::size_t k) const;
  void drop_upper() const;

  const PoseSpace* space_;
  std::uint64_t eps_units_;
  std::uint32_t mass_bits_;
  std::uint64_t band_width_;
  BeliefTable offset_;
  std::size_t retired_allocations_ = 0;  // of offset tables replaced by forget_below
  std::size_t pairs_ = 0;
  std::uint64_t max_ = 0;
  std::vector<std::uint64_t> touched_, best_offset_, best_key_;
  BeliefTable band_;  // each band bin's offset as of its last fold (current while it is in the band)
  std::size_t band_pruned_size_ = 0;
  mutable BeliefTable upper_{16};          // best_past_band's bins (under best_.mutex when read or made)
  mutable std::uint64_t upper_floor_ = 0;  // 0: upper_ is not kept
  mutable std::size_t upper_made_size_ = 0;
  // best_bins' last answer: the best `asked` bins (or all, if fewer), until the belief changes. A moved belief
  // starts without one (it is only a cache).
  struct KeptBest {
    std::mutex mutex;
    std::vector<BinOffset> bins;
    std::size_t asked = 0;
    KeptBest() = default;
    KeptBest(KeptBest&&) noexcept {}
    KeptBest& operator=(KeptBest&&) noexcept {
      bins.clear();
      asked = 0;
      return *this;
    }
  };
  mutable KeptBest best_;
};

}  // namespace sva
