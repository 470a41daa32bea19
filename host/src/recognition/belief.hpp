#pragma once
// The belief over (object, pose bin) in the log domain (DESIGN 4, Eq 3-5).
// Every pair factor has a floor: factor(x) = eps + S_p(x), with S_p the pair's
// votes normalised over the whole space. The common eps^P cancels, so the
// belief is stored as offset(x) = sum_p log2(1 + S_p(x) / eps) for touched bins
// only; every untouched bin has offset 0 (the shared baseline).
//
// Offsets and the estimate's reductions are integers (sva_belief_math.h):
// fixed-point bits of evidence, summed in any order with the same result. So a
// belief can live wherever its backend folds (host memory for the CPU
// reference, device memory for Vulkan) and every backend answers alike:
// BeliefState is the interface, `Belief` the CPU reference, and the estimate
// is computed once, from a BeliefState's reductions (recognition/estimate.hpp).
#include <cstdint>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "recognition/bin_accumulator.hpp"
#include "recognition/pose_space.hpp"

namespace sva {

struct PairVotes;

// A touched bin and its offset in belief units (2^32 per bit of evidence).
struct BinOffset {
  std::uint64_t key = 0;
  std::uint64_t offset = 0;
  bool operator==(const BinOffset&) const = default;
};

// The integer reductions an estimate needs, per object.
struct BeliefSummary {
  std::uint64_t max_offset = 0;             // M over all touched bins (0 when none)
  std::vector<std::uint64_t> touched;       // touched bins
  std::vector<std::uint64_t> touched_mass;  // sum of sva_exp2_neg_units(M - offset, mass_bits) over touched bins
  std::vector<std::uint64_t> best_offset;   // largest offset
  std::vector<std::uint64_t> best_key;      // smallest key with the largest offset (when touched > 0)
  bool operator==(const BeliefSummary&) const = default;
};

class BeliefState {
 public:
  virtual ~BeliefState() = default;
  // Forgets every bin; the table's allocation is kept for the next session.
  virtual void reset() = 0;
  // Belief tables allocated so far: the first, and one per growth or rehash (forgetting). A reset allocates none,
  // so a session after it allocates none until it outgrows the previous one's table.
  virtual std::size_t table_allocations() const = 0;
  virtual std::size_t pairs_folded() const = 0;
  virtual std::size_t touched() const = 0;
  virtual BeliefSummary summarise() const = 0;
  // The k bins with the largest offsets, ties to the smaller key, best first.
  virtual std::vector<BinOffset> best_bins(std::size_t k) const = 0;
  // The offsets of `keys` (0 for untouched bins).
  virtual std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const = 0;
  // Every touched bin, in key order (tests and inspection; costs a full read-out).
  virtual std::vector<BinOffset> table() const = 0;
  // Bounded memory (FilterOptions::belief_budget_bins): forgets every touched
  // bin whose offset is below `below`, except the bins in `keep` (sorted keys:
  // the neighbourhoods of the objects' best bins, which the estimate reads),
  // so that it counts as untouched (offset 0) again. The same bins on every
  // backend. Returns how many were forgotten.
  virtual std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) = 0;
};

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
  bool add(const std::vector<BinOffset>& terms, std::uint32_t count);

  void reset() override;
  std::size_t table_allocations() const override { return retired_allocations_ + offset_.allocations(); }
  std::size_t pairs_folded() const override { return pairs_; }
  std::size_t touched() const override { return offset_.size(); }
  BeliefSummary summarise() const override;
  std::vector<BinOffset> best_bins(std::size_t k) const override;
  std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const override;
  std::vector<BinOffset> table() const override;
  std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) override;

  std::uint64_t offset(std::uint64_t key) const { return offset_.get(key); }

 private:
  // Offsets only grow, so the fold keeps the estimate's reductions up to date
  // (DESIGN's "no pass over every bin per estimate"): the maximum, each
  // object's touched count and best bin directly, and the object masses and
  // top-k through the *band*: the bins within band_width_ of the maximum, the
  // only ones whose weight 2^(offset - M) at mass_bits is not 0. A bin leaves
  // the band only as the maximum grows, so the band set holds every bin in
  // the band (and some stale ones, skipped when read, pruned as it grows).
  bool in_band(std::uint64_t offset) const { return max_ - offset < band_width_; }
  void note(std::uint64_t key, std::uint64_t offset, bool inserted);
  void prune_band();

  const PoseSpace* space_;
  std::uint64_t eps_units_;
  std::uint32_t mass_bits_;
  std::uint64_t band_width_;
  BinTable<std::uint64_t> offset_;
  std::size_t retired_allocations_ = 0;  // of offset tables replaced by forget_below
  std::size_t pairs_ = 0;
  std::uint64_t max_ = 0;
  std::vector<std::uint64_t> touched_, best_offset_, best_key_;
  BinTable<std::uint8_t> band_;
  std::size_t band_pruned_size_ = 0;
};

}  // namespace sva
