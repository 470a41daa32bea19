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
// is computed once, from a BeliefState's reductions (estimate/candidates.hpp).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sva {

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

// What stage 1 of an estimate reads by key, as estimate/hypotheses.hpp's hypothesis_keys chooses it: up to `modes`
// distinct modes among the `mode_best` best bins (no two of one object within `suppress` grid steps), then every
// touched object's best bin, and the neighbourhood of each within `radius` steps (at least 1). A device chooses the
// same keys after an update, in its submission (belief_hoods.comp), so that the estimate after it reads nothing more;
// `on` false: not asked. With pose priors (`prior`: PoseWeighting::device_terms, kPriorDeviceFloats per object), the
// modes' candidates are ordered by evidence plus prior, and an object's best bin is its best under its prior among
// the `prior_best` best bins.
struct KeyChoice {
  bool on = false;
  std::uint32_t modes = 0, best = 0;
  int suppress = 0, radius = 1;
  std::uint32_t mode_best = 0;   // of `best`, the modes' candidates (0: all `best`)
  std::uint32_t prior_best = 0;  // of `best`, an object's best bin's under its prior
  std::vector<float> prior;      // empty: no pose prior
};
// Floats per object of KeyChoice::prior (SVA_PRIOR_FLOATS), and the most candidates a device orders by a prior in
// its one invocation (SVA_PRIOR_MOST_CANDIDATES): a longer list is the host's to choose.
inline constexpr std::size_t kPriorDeviceFloats = 16;
inline constexpr std::size_t kPriorMostCandidates = 256;

class BeliefState {
 public:
  virtual ~BeliefState() = default;
  // Forgets every bin; the table's allocation is kept for the next session.
  virtual void reset() = 0;
  // Belief tables allocated so far: the first (the CPU reference's: one per shard), and one per growth or rehash
  // (forgetting). A reset allocates none, so a session after it allocates none until it outgrows the previous one's.
  virtual std::size_t table_allocations() const = 0;
  virtual std::size_t pairs_folded() const = 0;
  virtual std::size_t touched() const = 0;
  // Bytes its tables hold now (host memory for the CPU reference, device memory for Vulkan): a live session's
  // memory in a batch is mostly this.
  virtual std::size_t table_bytes() const = 0;
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

}  // namespace sva
