#pragma once
// The estimate (DESIGN 4): from any backend's belief reductions, the posterior
// per object, the best object's best bin refined below the bin size, and the
// top-k bins over all objects. Computed once, here, for every backend.
#include <cstdint>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "recognition/belief.hpp"
#include "recognition/pose_space.hpp"

namespace sva {

struct BinHypothesis {
  std::uint64_t key = 0;
  std::uint32_t object = 0;
  RigidPose pose;          // bin centre
  double probability = 0;  // posterior mass of the bin
};

struct BeliefEstimate {
  std::uint32_t object = 0;
  std::vector<double> object_probability;  // sums to 1
  bool pose_valid = false;                 // the best object has a touched bin
  std::uint64_t best_key = 0;
  RigidPose pose;            // the histogram's estimate, `parabolic_pose` (the recognizer then refines it against
                             // the surface: recognition/pose_refinement.hpp, sva::Estimate::pose)
  RigidPose parabolic_pose;  // below the bin size: per-axis parabolic peak of the log-belief around the best bin
  RigidPose bin_pose;        // centre of the best bin
  // Distinct modes of the best object, best first, for the fine pose to start
  // from: the parabolic peak of the best bin, then the centres of the next best
  // bins that are not neighbours of an earlier mode (at most `modes` in all).
  std::vector<RigidPose> modes;
  std::vector<BinHypothesis> top;
};

// The belief's total mass in the units of object_probability's (a bin at the maximum weighs 2^mass_bits).
// `object_weight`: the prior per object (largest 1; empty: flat), as in estimate().
double total_mass(const BeliefSummary& summary, const PoseSpace& space, std::span<const double> object_weight = {});
// Posterior per object from the reductions (untouched bins at the baseline).
std::vector<double> object_probability(const BeliefSummary& summary, const PoseSpace& space);
// The estimate of any backend's belief: best object, its best bin refined
// below the bin size, up to `modes` distinct modes of that object, and the
// top-k bins over all objects. `object_weight` (per object, largest 1; empty: flat) is a prior over objects: it
// scales every bin of an object (a per-object offset of log2(weight) in the log-domain belief), so it moves the
// object posterior and the bins' probabilities but not which bin of an object is best, nor the top bins' order.
BeliefEstimate estimate(const BeliefState& belief, const PoseSpace& space, std::size_t top_k, std::size_t modes = 1,
                        std::span<const double> object_weight = {});

}  // namespace sva
