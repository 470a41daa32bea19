#pragma once
// The one interface behind which backends live (the CPU reference and
// Vulkan). A backend owns the sessions' beliefs (make_belief: host memory or
// device memory) and, given a batch of observed pairs from any number of
// independent sessions, votes every pair and folds it into its session's
// belief (vote_and_fold). vote() returns the pairs' votes instead, per pose
// bin as fixed-point masses sorted by key: the contract the backends are
// tested against. The per-match math (sva_vote_math.h) and the fold
// (sva_belief_math.h) are shared text; pair keys and the estimate are the
// caller's, so every backend gives the same answers.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "backends/backend_stats.hpp"
#include "belief/belief_state.hpp"
#include "map/pair_map.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// One end of an observed pair (robot frame, mm).
struct ObservedPatch {
  float position[3];
  float normal[3];  // unit
  float norm_conf;  // Algorithm 1
};

struct PairQuery {
  ObservedPatch a, b;
  std::uint32_t key_begin = 0, key_end = 0;  // range in VoteBatch::keys
  std::uint32_t session = 0;                 // index in VoteBatch::object_active rows
  std::uint32_t fold_count = 1;              // times the pair's factor is folded (2: both orders of Eq 5)
};

struct VoteBatch {
  std::vector<PairQuery> pairs;
  std::vector<PairKeyWeight> keys;
  std::uint32_t sessions = 0;
  // sessions x objects: 1 where the session still votes for the object
  // (RecognizerOptions::object_prune_probability); empty = all active.
  std::vector<std::uint8_t> object_active;
};

struct PairStats {
  std::uint64_t matches = 0;        // map pairs aligned (once per map pair, summed over the keys it shares)
  std::uint64_t votes = 0;          // beta samples inside the pose space
  std::uint64_t votes_outside = 0;  // beta samples outside it (or not planar)
  std::uint64_t votes_zero = 0;     // samples inside whose mass rounds to 0 units (counted, never silently lost)
  bool folded = false;              // vote_and_fold: the pair had vote mass and was folded
  // The work, where the backend counts it (0 where not): map entries under the pair's keys, slots probed in the
  // pair's vote table, bins of the pair (its fold terms) and slots probed in the session's belief to add them.
  std::uint64_t entries = 0, table_probes = 0, bins = 0, belief_probes = 0;
  // Atomic operations on the pair's vote table (a device's: key compare-and-swaps and adds; 0 on the CPU).
  std::uint64_t atomics = 0;
};

// An update's work (BackendStats::last_work): its pairs' counts, summed (PairStats or PairVotes).
template <class Stats>
BatchRecognizer::Work work_of(const std::vector<Stats>& pairs) {
  BatchRecognizer::Work w;
  w.pairs = pairs.size();
  for (const PairStats& p : pairs) {
    w.entries += p.entries;
    w.matches += p.matches;
    w.votes += p.votes;
    w.table_probes += p.table_probes;
    w.bins += p.bins;
    w.belief_probes += p.belief_probes;
    w.atomics += p.atomics;
  }
  return w;
}

struct PairVotes : PairStats {
  std::vector<std::uint64_t> keys;  // strictly increasing pose-bin keys
  std::vector<std::int64_t> mass;   // fixed point (SVA_FIXED_ONE = 1)
};

struct VoteSettings {
  float likelihood_cutoff =
      0.0f;              // matches whose likelihood (summed over their shared keys) is below this cast no vote
  unsigned threads = 0;  // CPU: 0 = util::default_threads()
};

class VoteBackend {
 public:
  virtual ~VoteBackend() = default;
  virtual std::vector<PairVotes> vote(const VoteBatch& batch) = 0;
  // A fresh belief (no pair folded) that lives with this backend.
  virtual std::unique_ptr<BeliefState> make_belief(const PoseSpace& space, double eps) = 0;
  // `n` of them, for a batch's sessions: a device empties them all in one submission, where each new belief emptied
  // its table in a round trip of its own (a thousand sessions' batch made a thousand).
  virtual std::vector<std::unique_ptr<BeliefState>> make_beliefs(const PoseSpace& space, double eps, std::size_t n) {
    std::vector<std::unique_ptr<BeliefState>> made;
    for (std::size_t i = 0; i < n; ++i) made.push_back(make_belief(space, eps));
    return made;
  }
  // Votes every pair of the batch and folds it into beliefs[pair.session]
  // (each made by this backend's make_belief). Returns per-pair statistics.
  virtual std::vector<PairStats> vote_and_fold(const VoteBatch& batch, std::span<BeliefState* const> beliefs) = 0;
  // Reads ahead, for many sessions' beliefs (each made by this backend), what their estimates read first: the
  // summary and the `best_bins` best bins. A device runs each pass once for all of them, where each session's
  // estimate made a round trip per pass; the beliefs' reads after it return what came back (the same answers).
  // The CPU reference reads its own memory: nothing to read ahead. `keys` (one per belief, or none): how each
  // estimate chooses the bins it reads by key, for a device to choose them in the next update too.
  virtual void read_ahead(std::span<const BeliefState* const> beliefs, std::size_t best_bins,
                          std::span<const KeyChoice> keys = {}) {
    (void)beliefs, (void)best_bins, (void)keys;
  }
  // Looks up keys[i]'s offsets in beliefs[i] for all of them at once (a device: one submission), where each
  // session's estimate made its own lookups; a belief's offsets() of keys among them then returns what came back,
  // until it changes. The CPU reference: nothing to look up ahead.
  virtual void look_up_ahead(std::span<const BeliefState* const> beliefs,
                             std::span<const std::vector<std::uint64_t>> keys) {
    (void)beliefs, (void)keys;
  }
  // Empties many sessions' beliefs (each made by this backend) for new sessions, as BeliefState::reset() does each:
  // a device empties them all in one submission, where each reset was a round trip of its own (a batch's group
  // starts with one for every session).
  virtual void reset_beliefs(std::span<BeliefState* const> beliefs) {
    for (BeliefState* b : beliefs) b->reset();
  }
  virtual const char* name() const = 0;
  // What runs the votes, the last update's timings and the counters so far.
  virtual BackendStats statistics() const = 0;
};

// The CPU reference backend: the executable specification of the vote step.
std::unique_ptr<VoteBackend> make_cpu_vote_backend(const PairMap& map, const PoseSpace& space,
                                                   const VoteSettings& settings);

}  // namespace sva
