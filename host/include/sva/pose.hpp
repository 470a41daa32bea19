#pragma once
// Rigid poses and object symmetries, in millimetres and radians.
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <vector>

namespace sva {

// x_world = R * x_object + T.
struct RigidPose {
  glm::dmat3 R{1.0};
  glm::dvec3 T{0.0};

  glm::dvec3 apply(const glm::dvec3& p) const { return R * p + T; }
  glm::dvec3 rotate(const glm::dvec3& v) const { return R * v; }
  RigidPose inverse() const {
    glm::dmat3 Rt = glm::transpose(R);
    return {Rt, -(Rt * T)};
  }
  friend RigidPose operator*(const RigidPose& a, const RigidPose& b) { return {a.R * b.R, a.R * b.T + a.T}; }
};

// The symmetry of an object, used by the angular error of Eq 22 and the
// translational error: a rotation S about the axis through `point` maps the
// object onto itself, x -> S (x - point) + point.
struct Symmetry {
  enum class Kind { none, axis, discrete };
  Kind kind = Kind::none;
  glm::dvec3 axis{0.0, 0.0, 1.0};     // Kind::axis: the axis of revolution (object frame)
  std::vector<glm::dmat3> rotations;  // Kind::discrete: the group, identity included
  glm::dvec3 point{0.0};              // a point of the axis (object frame, mm)
};

}  // namespace sva
