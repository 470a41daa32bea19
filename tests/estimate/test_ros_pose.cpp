// to_ros (estimate/ros_pose.cpp): the report stage's hypothesis in geometry_msgs/PoseWithCovariance's units
// (docs/api.md, "Mapping an Estimate onto vision_msgs/Detection3D").
#include <catch2/catch.hpp>

#include <sva/recognizer.hpp>

#include <cmath>

using namespace sva;

TEST_CASE("to_ros: metres, an x y z w quaternion with w >= 0, and the covariance in metres") {
  PoseHypothesis h;
  const double a = 2.5;  // about z: q = (0, 0, sin(a/2), cos(a/2))
  h.pose.R = glm::dmat3(std::cos(a), std::sin(a), 0.0, -std::sin(a), std::cos(a), 0.0, 0.0, 0.0, 1.0);
  h.pose.T = {1000.0, -250.0, 5.0};
  for (std::size_t i = 0; i < 36; ++i) h.covariance[i] = static_cast<double>(i + 1);
  const RosPose r = to_ros(h);
  CHECK(r.position[0] == Approx(1.0));
  CHECK(r.position[1] == Approx(-0.25));
  CHECK(r.position[2] == Approx(0.005));
  CHECK(r.orientation[0] == Approx(0.0).margin(1e-12));
  CHECK(r.orientation[1] == Approx(0.0).margin(1e-12));
  CHECK(r.orientation[2] == Approx(std::sin(a / 2)));
  CHECK(r.orientation[3] == Approx(std::cos(a / 2)));
  CHECK(r.covariance[0] == Approx(1e-6));    // x x: mm^2 to m^2
  CHECK(r.covariance[3] == Approx(4e-3));    // x rotX: mm rad to m rad
  CHECK(r.covariance[18] == Approx(19e-3));  // rotX x
  CHECK(r.covariance[21] == Approx(22.0));   // rotX rotX: rad^2
  // A half turn about x: w = 0 and the axis's sign is free; a rotation just short of it: w > 0, never w < 0.
  h.pose.R = glm::dmat3(1.0, 0.0, 0.0, 0.0, std::cos(3.1), std::sin(3.1), 0.0, -std::sin(3.1), std::cos(3.1));
  const RosPose near_half = to_ros(h);
  CHECK(near_half.orientation[3] == Approx(std::cos(1.55)));
  CHECK(near_half.orientation[0] == Approx(std::sin(1.55)));
}
