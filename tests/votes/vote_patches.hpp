#pragma once
// Test inputs for the shared vote math (sva_vote_math.h): double-precision geometry as the header's float
// patches, and a pose space's grid. Used by tests/votes and tests/backends/cpu.
#include <glm/glm.hpp>

#include "votes/pose_space.hpp"
#include "votes/vote_math.hpp"

namespace sva::test {

inline vote_math::vec3 f3(const glm::dvec3& v) {
  return vote_math::vec3(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
}

inline vote_math::SvaPatch patch(const glm::dvec3& p, const glm::dvec3& n, float conf = 1.0f) {
  vote_math::SvaPatch s;
  s.p = f3(p);
  s.n = f3(n);
  s.conf = conf;
  return s;
}

inline vote_math::SvaPoseGrid grid_of(const PoseSpaceSpec& spec) { return PoseSpace(spec, 1).grid(); }

}  // namespace sva::test
