#pragma once
// What the robot believed before touching (from vision, say), so that touch refines what a camera saw
// (docs/api.md, "Priors").
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>

#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace sva {

// A Gaussian over one object's pose (a camera's detection), in the robot frame: over the position, and optionally
// over the rotation (by the angle between the rotation and the mean's). Its weight at a pose is
//   exp(-|T - position|^2 / (2 position_sigma_mm^2) - angle(R, rotation)^2 / (2 rotation_sigma_rad^2)),
// 1 at the mean (not a normalised density: it lowers the object's bins away from the mean, and leaves other objects').
struct PosePrior {
  glm::dvec3 position{0.0};       // mean position of the object's origin (RigidPose::T), mm
  double position_sigma_mm = 0;   // > 0
  bool has_rotation = false;      // false: any rotation is as likely
  glm::dmat3 rotation{1.0};       // mean rotation (RigidPose::R), when has_rotation
  double rotation_sigma_rad = 0;  // > 0 when has_rotation
};

struct Prior {
  // Per object id: prior probabilities (any positive scale; finite, >= 0, not all 0). Empty: flat. They enter
  // the log-domain belief as a per-object offset of log2(p / max p) added to every bin of the object at
  // estimate time: exact, the same on every backend, and free of the fold.
  std::vector<double> object_probability;
  // Per object id: a Gaussian pose prior, or none (empty: none for any object). Applied at estimate time where
  // the estimate reads bins, exactly there: the choice of each object's best bin and its sub-bin peak, and the
  // distinct hypotheses' masses and order. The belief is sparse, so the bins the estimate does not read are not
  // reweighted, and the object probabilities are the evidence's (and the object prior's) alone (docs/api.md,
  // "Priors": what it does and does not do). Place the pose space's box from it with pose_space_around.
  std::vector<std::optional<PosePrior>> object_pose;
};

// The pose space's box placed around a pose prior: the grid of `grid`, centred on the prior's mean position with
// a half side of `sigmas` position sigmas (and turned by its mean rotation when it has one, so the rotation grid
// is centred on it too).
inline PoseSpaceSpec pose_space_around(const PoseSpaceSpec& grid, const PosePrior& prior, double sigmas = 3.0) {
  return placed_pose_space(grid, prior.position, sigmas * prior.position_sigma_mm,
                           prior.has_rotation ? prior.rotation : glm::dmat3(1.0));
}

}  // namespace sva
