#include "training/session_sampling.hpp"

#include <sva/base/portable_math.hpp>

#include <cmath>
#include <numbers>

namespace sva {

glm::dmat3 uniform_rotation(util::Rng& rng) {
  // Shoemake's subgroup algorithm: uniform on S^3, hence Haar on SO(3).
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double t1 = 2.0 * std::numbers::pi * u2, t2 = 2.0 * std::numbers::pi * u3;
  const glm::dquat q(b * pmath::cos(t2), a * pmath::sin(t1), a * pmath::cos(t1), b * pmath::sin(t2));  // (w, x, y, z)
  return glm::mat3_cast(glm::normalize(q));
}

RigidPose random_pose(util::Rng& rng, const PoseSpaceSpec& space) {
  RigidPose p;
  const double lo = space.translation_min_mm, hi = space.translation_max_mm;
  if (space.kind == PoseSpaceSpec::Kind::spatial) {
    p.R = uniform_rotation(rng);
    p.T = {rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)};
  } else {
    const double angle = rng.uniform(-std::numbers::pi, std::numbers::pi);
    const double c = pmath::cos(angle), s = pmath::sin(angle);
    p.R = glm::dmat3(glm::dvec3(c, s, 0.0), glm::dvec3(-s, c, 0.0), glm::dvec3(0.0, 0.0, 1.0));
    p.T = {rng.uniform(lo, hi), rng.uniform(lo, hi), 0.0};
  }
  return p;
}

Reading transform_reading(const Reading& reading, const RigidPose& pose) {
  Reading r = reading;
  r.position = pose.apply(reading.position);
  r.normal = pose.rotate(reading.normal);
  r.x_axis = pose.rotate(reading.x_axis);
  return r;
}

}  // namespace sva
