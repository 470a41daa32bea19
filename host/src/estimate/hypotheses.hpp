#pragma once
// Distinct hypotheses (docs/api.md): the belief's modes after non-maximum
// suppression in pose space, each with its posterior mass and a covariance
// from the belief around it. Read through BeliefState (best_bins, offsets)
// only, so every backend gives the same hypotheses, bit for bit.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "belief/belief_state.hpp"
#include "estimate/pose_prior.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// A mode in the grid's frame (PoseSpace::to_robot places it in the robot frame).
struct ModeHypothesis {
  std::uint32_t object = 0;
  std::uint64_t key = 0;   // the mode's best bin
  RigidPose pose;          // the parabolic peak of the log-belief around that bin
  double probability = 0;  // posterior mass of the bins within the radius (not already a stronger mode's)
  // Row-major 6 x 6 in ROS PoseWithCovariance order (x, y, z, rotation about X, Y, Z): weighted second moments
  // of the bins within the radius plus the bins' quantisation variance (width^2 / 12). Planar: z and the
  // rotations about X and Y are fixed by the plane (0 rows and columns).
  std::array<double, 36> covariance{};
};

struct HypothesisSet {
  std::vector<ModeHypothesis> modes;       // strongest peak first, no two within `radius` of each other
  std::vector<ModeHypothesis> per_object;  // per object id: the mode of its best bin
  std::vector<bool> per_object_valid;      // the object has a touched bin
};

// Up to `count` modes over all objects, chosen greedily from the best bins (the strongest first; a bin within
// `radius` grid steps of a stronger mode of the same object is suppressed), and every touched object's best
// mode. `summary` is belief.summarise(); `object_weight` a prior over objects (sva::estimate), which scales the
// masses (the modes' order is the evidence's). `pose_weighting` (a pose prior) orders the candidate bins by
// evidence plus prior before the suppression, chooses each object's mode as best_bin_under_prior does, and
// weighs every bin of a mode's mass and spread by the prior at its centre; the masses stay over the evidence's
// total (the prior's normaliser would need every bin), so they compare modes but need not sum to an object's
// probability. Each object's neighbourhood and moments are computed on `threads` workers (0: all cores), the same
// answers for any count.
HypothesisSet hypotheses(const BeliefState& belief, const PoseSpace& space, const BeliefSummary& summary,
                         std::size_t count, int radius, std::span<const double> object_weight = {},
                         const PoseWeighting& pose_weighting = {}, unsigned threads = 0);

// The bins hypotheses() reads by key for the same arguments (its centres' neighbourhoods, which also hold the
// parabola's bins around each object's best bin that the candidates stage refines): what a device looks up for
// many sessions at once before their estimates read them (VoteBackend::look_up_ahead).
std::vector<std::uint64_t> hypothesis_keys(const BeliefState& belief, const PoseSpace& space,
                                           const BeliefSummary& summary, std::size_t count, int radius,
                                           const PoseWeighting& pose_weighting = {});

// The best bins the hypotheses' `count` modes are chosen from (the best bin alone for one mode without a prior).
std::size_t mode_candidates(std::size_t count, bool pose_prior);

// The covariance of a mode carried into the robot frame by the workspace rotation (both 3 x 3 blocks turn).
std::array<double, 36> covariance_to_robot(const std::array<double, 36>& grid, const glm::dmat3& workspace);

}  // namespace sva
