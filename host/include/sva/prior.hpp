#pragma once
// What the robot believed before touching (from vision, say), so that touch refines what a camera saw
// (docs/api.md, "Priors").
#include <vector>

namespace sva {

struct Prior {
  // Per object id: prior probabilities (any positive scale; finite, >= 0, not all 0). Empty: flat. They enter
  // the log-domain belief as a per-object offset of log2(p / max p) added to every bin of the object at
  // estimate time: exact, the same on every backend, and free of the fold.
  std::vector<double> object_probability;
};

// A pose prior (a camera's pose estimate) enters as the pose space's workspace frame: placed_pose_space(grid,
// camera_pose.T, 3 * position_sigma_mm) puts the box the belief covers around it (docs/api.md, "Priors").

}  // namespace sva
