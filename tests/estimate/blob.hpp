#pragma once
// The fine pose's test object (tests/estimate/test_fine_pose.cpp, test_fit_problem.cpp): an asymmetric blob, an
// ellipsoid of about 60 x 45 x 30 mm whose radius grows along +x and +y and twists with y z, so that no rotation maps
// it onto itself. Normals by finite differences.
#include <glm/glm.hpp>

#include <cmath>

namespace sva::test {

inline glm::dvec3 blob_point(double theta, double phi) {
  const glm::dvec3 u(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  const double grow = 1.0 + 0.25 * u.x + 0.15 * u.y + 0.2 * u.y * u.z;
  return grow * glm::dvec3(30.0, 22.0, 15.0) * u;
}

// The outward unit normal at (theta, phi), away from the poles.
inline glm::dvec3 blob_normal(double theta, double phi) {
  const double h = 1e-5;
  const glm::dvec3 dt = blob_point(theta + h, phi) - blob_point(theta - h, phi);
  const glm::dvec3 dp = blob_point(theta, phi + h) - blob_point(theta, phi - h);
  const glm::dvec3 n = glm::normalize(glm::cross(dt, dp));
  return glm::dot(n, blob_point(theta, phi)) < 0.0 ? -n : n;
}

}  // namespace sva::test
