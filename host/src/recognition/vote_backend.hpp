#pragma once
// The one interface behind which vote backends live (CPU reference now, Vulkan
// next). A call takes a batch of observed pairs from any number of independent
// recognition sessions and returns, per pair, its votes folded per pose bin:
// fixed-point masses sorted by bin key. The backend does the per-match math
// (sva_vote_math.h); everything around it (pair keys, the log-domain belief,
// the estimate) is the caller's, so every backend gives the same answers.
#include <cstdint>
#include <memory>
#include <vector>

#include "map/pair_map.hpp"
#include "recognition/pose_space.hpp"

namespace sva {

// One end of an observed pair (robot frame, mm).
struct ObservedPatch {
  float position[3];
  float normal[3];  // unit
  float norm_conf;  // Algorithm 1
};

// A map key the observed pair looks up, with w_obs = Pa(ca) Pb(cb) Pd(d).
struct PairKeyWeight {
  std::uint32_t key;
  float weight;
};

struct PairQuery {
  ObservedPatch a, b;
  std::uint32_t key_begin = 0, key_end = 0;  // range in VoteBatch::keys
  std::uint32_t session = 0;                 // index in VoteBatch::object_active rows
};

struct VoteBatch {
  std::vector<PairQuery> pairs;
  std::vector<PairKeyWeight> keys;
  std::uint32_t sessions = 0;
  // sessions x objects: 1 where the session still votes for the object
  // (RecognizerOptions::object_prune_probability); empty = all active.
  std::vector<std::uint8_t> object_active;
};

struct PairVotes {
  std::vector<std::uint64_t> keys;   // strictly increasing pose-bin keys
  std::vector<std::int64_t> mass;    // fixed point (SVA_FIXED_ONE = 1)
  std::uint64_t matches = 0;         // map entries aligned
  std::uint64_t votes = 0;           // beta samples inside the pose space
  std::uint64_t votes_outside = 0;   // beta samples outside it (or not planar)
};

struct VoteSettings {
  float likelihood_cutoff = 0.0f;  // matches with w_obs * entry_weight below this cast no vote
  unsigned threads = 0;            // CPU: 0 = util::default_threads()
};

class VoteBackend {
 public:
  virtual ~VoteBackend() = default;
  virtual std::vector<PairVotes> vote(const VoteBatch& batch) = 0;
  virtual const char* name() const = 0;
};

// The CPU reference backend: the executable specification of the vote step.
std::unique_ptr<VoteBackend> make_cpu_vote_backend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings);

}  // namespace sva
