#pragma once
// The recognizer's pose space (paper Sec 5): the box of object poses the belief
// is discretised over, and where that box lies in the robot's workspace.
#include <sva/pose.hpp>

#include <glm/glm.hpp>

namespace sva {

struct PoseSpaceSpec {
  enum class Kind { spatial, planar };  // spatial: 6-DOF (T xyz, Rodrigues xyz); planar: x, y, angle about z
  Kind kind = Kind::spatial;
  int translation_bins = 50;
  double translation_min_mm = -200.0;  // per axis, in the workspace frame
  double translation_max_mm = 200.0;
  int rotation_bins = 9;  // per Rodrigues axis (planar: over [-pi, pi])
  // The workspace frame: where the box lies in the robot frame (x_robot = workspace.apply(x_box)). The map is
  // trained around the object's own origin, so the same map recognises an object anywhere in the robot's
  // workspace once the box is placed where the object may lie. Readings stay in the robot frame and every
  // estimated pose is in the robot frame. Identity (the default): the box is in the robot frame itself.
  // Planar spaces accept a rotation about z only (the object lies on the plane).
  RigidPose workspace;
};

// The grid of `grid` (kind, bins), its box a cube of half side `half_extent_mm` centred on `centre` (robot
// frame, mm) and turned by `rotation` (the workspace frame's axes in the robot frame).
inline PoseSpaceSpec placed_pose_space(PoseSpaceSpec grid, const glm::dvec3& centre, double half_extent_mm,
                                       const glm::dmat3& rotation = glm::dmat3(1.0)) {
  grid.translation_min_mm = -half_extent_mm;
  grid.translation_max_mm = half_extent_mm;
  grid.workspace.R = rotation;
  grid.workspace.T = centre;
  return grid;
}

}  // namespace sva
