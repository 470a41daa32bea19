#pragma once
// The caller's pose priors (sva::PosePrior, docs/api.md "Priors") as the estimate's stages read them: a Gaussian
// per object, in log2 weights at poses of the grid, which move an object's best bin, its parabolic peak and the
// order of its modes, and never the object posterior.
#include <cstdint>
#include <optional>
#include <vector>

#include <sva/pose.hpp>
#include <sva/prior.hpp>

#include "belief/belief_state.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// A Gaussian pose prior per object (robot frame) as log2 weights at poses of the grid: 0 at the mean, negative
// elsewhere, 0 for an object without one. The estimate adds them to the log-belief (in bits) of the bins it reads.
class PoseWeighting {
 public:
  PoseWeighting() = default;
  // `per_object`: empty, or one entry per object of `space` (checked by the recognizer).
  PoseWeighting(std::vector<std::optional<PosePrior>> per_object, const PoseSpace& space);
  bool empty() const { return per_object_.empty(); }
  bool applies_to(std::uint32_t object) const { return object < per_object_.size() && per_object_[object]; }
  // log2 of the prior's weight at `grid_pose` (the grid's frame) of `object`, or at the centre of bin `key`.
  double log2_weight(std::uint32_t object, const RigidPose& grid_pose) const;
  double log2_weight(std::uint64_t key) const;
  // The same Gaussians as a device evaluates them (belief_hoods.comp), kPriorDeviceFloats floats per object in the
  // grid's frame (shaders/include/sva_gpu_layout.h, SVA_PRIOR_FLOATS, says which): empty without priors.
  std::vector<float> device_terms() const;

 private:
  std::vector<std::optional<PosePrior>> per_object_;
  const PoseSpace* space_ = nullptr;
};

// The candidates a pose prior chooses an object's best bin among: how many of the best bins (over all objects)
// are read.
constexpr std::size_t kPosePriorCandidates = 64;
// The object's best bin under a pose prior: the most evidence plus prior among its best bin and its bins among
// the kPosePriorCandidates best bins over all objects (the bins the estimate reads; an unread bin is not a
// candidate). Ties to the smaller key. `summary` is belief.summarise().
std::uint64_t best_bin_under_prior(const BeliefState& belief, const BeliefSummary& summary, std::uint32_t object,
                                   const PoseWeighting& prior);
// Bins ordered by their log-belief plus the pose prior's log2 weight, best first (ties keep best_bins' order:
// the smaller key first). Without a prior: as given.
std::vector<BinOffset> order_by_pose_prior(std::vector<BinOffset> bins, const PoseWeighting& prior);

}  // namespace sva
