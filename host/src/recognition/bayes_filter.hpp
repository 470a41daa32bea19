#pragma once
// The SVA Bayes filter of one recognition session (Eq 3-5): each new reading
// is paired with every earlier one in both orders (one order voted, folded
// twice: the orders cast the same votes), and the backend votes each pair and
// folds its factor into the session's log-domain belief, which lives
// with the backend (on the device for Vulkan). Several sessions can update in
// one backend call (update_sessions), which is how batch evaluation keeps a
// GPU busy.
#include <memory>
#include <span>
#include <vector>

#include "backends/vote_backend.hpp"
#include "belief/belief_state.hpp"
#include "map/pair_map.hpp"
#include "reading/observed_reading.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct FilterOptions {
  double eps = 1e-6;
  double object_prune_probability = 0.0;  // objects below this posterior stop receiving votes
  int max_pairs_per_update = 0;           // 0 = all; else pairs with the most recent readings
  // Bounded memory on long sessions: past this many touched bins, an update
  // forgets the bins more than forget_margin_bits bits of evidence below the
  // best one (the objects' best bins and their neighbourhoods are kept). 0 = no
  // bound. A forgotten bin's mass is already 0 in the estimate; it matters again
  // only if its region later becomes the best (a competing mode of a symmetric
  // object can): docs/recognition.md, "Bounded memory".
  std::size_t belief_budget_bins = std::size_t{1} << 22;
  unsigned forget_margin_bits = 256;
};

struct UpdateStats {
  std::size_t pairs = 0;         // ordered pairs (Eq 5) of this update
  std::size_t pairs_folded = 0;  // ordered pairs that had votes
  std::size_t pairs_voted = 0;   // pairs sent to the backend (one per earlier reading: both orders cast the same votes)
  std::uint64_t matches = 0;     // map pairs aligned (once per map pair, whatever keys it shares with the observed one)
  std::uint64_t votes = 0;
  std::uint64_t votes_outside = 0;
  std::uint64_t votes_zero = 0;    // votes inside the space whose mass rounds to 0 fixed-point units
  std::size_t bins_forgotten = 0;  // belief bins forgotten to keep within the budget (FilterOptions)
};

class BayesFilter {
 public:
  // The belief is made by `backend`, which must outlive the filter.
  BayesFilter(const PairMap& map, const PoseSpace& space, const FilterOptions& options, VoteBackend& backend);
  // `n` sessions of one backend, their beliefs made together (VoteBackend::make_beliefs: on a device, emptied in one
  // submission). The options are checked before any belief is made.
  static std::vector<std::unique_ptr<BayesFilter>> make_sessions(const PairMap& map, const PoseSpace& space,
                                                                 const FilterOptions& options, VoteBackend& backend,
                                                                 std::size_t n);

  // Adds one reading (as describe_reading and to_grid make it: checked, grid frame) and updates the belief.
  UpdateStats add(const ObservedReading& reading);
  void reset();
  // reset() of many sessions of one backend, their beliefs emptied together (VoteBackend::reset_beliefs).
  static void reset_all(std::span<BayesFilter* const> sessions);

  std::size_t readings() const { return readings_.size(); }
  // The session's readings so far (robot frame, validated), oldest first.
  const std::vector<ObservedReading>& observed() const { return readings_; }
  const BeliefState& belief() const { return *belief_; }
  VoteBackend& backend() const { return *backend_; }
  const UpdateStats& last_update() const { return last_; }
  const PoseSpace& space() const { return *space_; }
  const PairMap& map() const { return *map_; }

  // Batch building blocks: queue the pairs of `reading` (validated) as
  // `session`, then record the reading and the backend's statistics.
  void queue_pairs(const ObservedReading& reading, std::uint32_t session, VoteBatch* batch) const;
  UpdateStats record(const ObservedReading& reading, const PairQuery* queries, const PairStats* pairs,
                     std::size_t count);
  BeliefState& mutable_belief() { return *belief_; }
  // An update that threw after its backend began folding (Ctrl-C, a device
  // error) leaves the belief partly folded: the session refuses further use
  // with a clear error until reset().
  void mark_incomplete() { incomplete_ = true; }
  // After an update: keeps the belief within FilterOptions::belief_budget_bins; returns the bins forgotten.
  std::size_t keep_within_budget();
  void require_complete() const;

 private:
  // A filter around a belief its backend made; the options checked (check_options) by the caller.
  BayesFilter(const PairMap& map, const PoseSpace& space, const FilterOptions& options, VoteBackend& backend,
              std::unique_ptr<BeliefState> belief);
  static void check_options(const PairMap& map, const PoseSpace& space, const FilterOptions& options);

  const PairMap* map_;
  const PoseSpace* space_;
  FilterOptions options_;
  VoteBackend* backend_;
  std::unique_ptr<BeliefState> belief_;
  std::uint64_t max_pairs_;  // fixed-point headroom (belief_math::max_pairs)
  std::vector<ObservedReading> readings_;
  UpdateStats last_;
  std::size_t kept_after_forget_ = 0;  // touched bins the last forgetting kept (keep_within_budget)
  bool incomplete_ = false;
};

// Updates several independent sessions, each with its next reading (checked, grid frame), in one call of their
// common backend; results equal calling add() on each session in turn.
std::vector<UpdateStats> update_sessions(const std::vector<BayesFilter*>& sessions,
                                         const std::vector<ObservedReading>& readings);

}  // namespace sva
