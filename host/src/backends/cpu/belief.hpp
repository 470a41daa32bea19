#pragma once
// The CPU reference belief (belief/belief_state.hpp says what a belief is): the offsets in open-addressing tables in
// host memory, folded pair by pair, split into shards by the bin's hash (backends/cpu/belief_shard.hpp) so that one
// session's pairs add their terms on every core at once.
#include <array>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "backends/cpu/belief_shard.hpp"
#include "backends/cpu/bin_accumulator.hpp"
#include "belief/belief_state.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct PairVotes;

// Shards of a belief: a fixed count, so that which shard holds a bin, and so every table's contents, do not depend on
// the thread count. 32 keep 16 workers' shares within a few percent of each other; an empty shard costs 2 KB.
inline constexpr unsigned kBeliefShardBits = 5;
inline constexpr std::size_t kBeliefShards = std::size_t{1} << kBeliefShardBits;
inline std::size_t belief_shard_of(std::uint64_t key) {
  // The low bits of the hash: each shard's table takes its homes from the high bits (BeliefTable).
  return static_cast<std::size_t>(hash::sva_hash64(key) & (kBeliefShards - 1));
}

// A pair's fold terms, grouped by the shard of their bin (each group in the pair table's slot order).
struct BeliefTerms {
  std::vector<BinOffset> terms;
  std::array<std::uint32_t, kBeliefShards + 1> begin{};  // shard s's terms: [begin[s], begin[s + 1])
  std::size_t size() const { return terms.size(); }
  bool empty() const { return terms.empty(); }
  std::span<const BinOffset> shard(std::size_t s) const {
    return std::span<const BinOffset>(terms).subspan(begin[s], begin[s + 1] - begin[s]);
  }
  // Terms given in any order, grouped (the order within a shard kept).
  static BeliefTerms grouped(std::span<const BinOffset> terms);
};

// A part of one pair's votes, summed per bin: a piece of its matches voted on a worker of its own (a pair far larger
// than the rest, backends/cpu/cpu_vote_backend.cpp). Its bins grouped by shard as BeliefTerms groups them, so that
// the parts are joined shard by shard on every worker (Belief::terms); and its mass.
struct ShardedVotes {
  std::vector<std::uint64_t> key;
  std::vector<std::int64_t> mass;  // > 0
  std::array<std::uint32_t, kBeliefShards + 1> begin{};
  std::uint64_t total = 0;
  // The accumulator's bins with votes, grouped.
  static void of(const BinAccumulator& votes, ShardedVotes* out);
};

// The CPU reference belief.
class Belief final : public BeliefState {
 public:
  // `threads`: the workers an estimate's passes over the shards use (0: the pool's default); the answers do not
  // depend on it.
  Belief(const PoseSpace& space, double eps, unsigned threads = 0);

  // Multiplies in one pair factor `count` times (count 2: both orders of Eq 5,
  // which cast the same votes). A pair with no vote mass leaves the belief
  // unchanged (it carries no information about the pose). Returns whether it folded.
  bool fold(const PairVotes& votes, std::uint32_t count = 1);
  // The same in two steps: the pair's per-bin offset increments, which only
  // read the belief's eps (pairs compute theirs in parallel), then their
  // addition (integers: the order of pairs does not matter).
  BeliefTerms terms(const BinAccumulator& votes) const;
  void terms(const BinAccumulator& votes, BeliefTerms* out) const;  // into *out, its capacity reused
  // A pair's terms from its votes in parts (each bin's mass the sum of its parts'), the shards joined in parallel on
  // `threads` workers: the terms of the pair's votes summed whole, in another order within a shard. *probes: the
  // slots the joins probed.
  void terms(std::span<const ShardedVotes> parts, unsigned threads, BeliefTerms* out, std::uint64_t* probes) const;
  bool add(const BeliefTerms& terms, std::uint32_t count);
  // Many pairs' terms (pair i `counts[i]` times), the shards added in parallel on `threads` workers (0: the pool's
  // default), each shard by one worker, the pairs in order. The same offsets as add() per pair. (*folded)[i]: whether
  // pair i folded; (*probes)[i]: the slots its additions probed.
  void add_all(std::span<const BeliefTerms> terms, std::span<const std::uint32_t> counts, unsigned threads,
               std::vector<std::uint8_t>* folded, std::vector<std::uint64_t>* probes);

  void reset() override;
  std::size_t table_allocations() const override;
  std::size_t pairs_folded() const override { return pairs_; }
  std::size_t touched() const override;
  std::size_t table_bytes() const override;
  BeliefSummary summarise() const override;
  std::vector<BinOffset> best_bins(std::size_t k) const override;
  std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const override;
  std::vector<BinOffset> table() const override;
  std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) override;

  std::uint64_t offset(std::uint64_t key) const { return shards_[belief_shard_of(key)].get(key); }
  // Slots of the offset tables probed by additions since they were last made or emptied (the work `sva bench` counts).
  std::uint64_t table_probes() const;

 private:
  void forget_best();  // the belief changed: best_bins' kept answer is stale

  const PoseSpace* space_;
  std::uint64_t eps_units_;
  std::vector<BeliefShard> shards_;
  std::size_t pairs_ = 0;
  unsigned threads_ = 0;
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
