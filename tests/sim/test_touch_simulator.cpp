// A planned touch pressed on the mesh (what `sva eval --policy active-sim` feeds the recognizer).
#include <catch2/catch.hpp>
#include <sva/error.hpp>
#include <sva/scene.hpp>
#include <sva/sim/touch_simulator.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace sva;

namespace {
double degrees_between(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}
}  // namespace

TEST_CASE("Touch simulator: a planned press lands where it was aimed, in the robot frame, with the arm's error") {
  const Scene scene = load_scene("tiny");  // die (80 mm cube) and brick, the realistic errors
  const sim::TouchSimulator press(scene);
  // The die turned 30 degrees about z and moved: the robot aims at its top face from above.
  RigidPose pose;
  const double a = std::numbers::pi / 6.0;
  pose.R = glm::dmat3(std::cos(a), std::sin(a), 0.0, -std::sin(a), std::cos(a), 0.0, 0.0, 0.0, 1.0);
  pose.T = {100.0, -50.0, 20.0};
  const glm::dvec3 aim_object{6.0, -4.0, 40.0};
  CandidateTouch touch;
  touch.position = pose.apply(aim_object);
  touch.approach = {0.0, 0.0, -1.0};
  const std::optional<Reading> r = press.press(0, pose, touch, 11);
  REQUIRE(r.has_value());
  CHECK(r->status == ControllerStatus::converged);
  // Where it was aimed (the controller re-centres, the arm errs by ~0.5 mm), on the top face, facing up.
  CHECK(glm::length(r->position - touch.position) < 6.0);
  CHECK(std::abs(r->position.z - touch.position.z) < 3.0);
  CHECK(degrees_between(r->normal, {0.0, 0.0, 1.0}) < 5.0);
  CHECK(std::abs(glm::dot(r->normal, r->x_axis)) < 1e-9);
  CHECK(r->pressure.size() == static_cast<std::size_t>(scene.sensor.elements()));
  // Deterministic for a seed; another seed turns the sensor about the approach.
  const std::optional<Reading> again = press.press(0, pose, touch, 11), other = press.press(0, pose, touch, 12);
  REQUIRE(again.has_value());
  CHECK(again->position == r->position);
  CHECK(again->pressure == r->pressure);
  REQUIRE(other.has_value());
  CHECK(other->x_axis != r->x_axis);
  // Aimed at empty space: no contact, no reading.
  touch.position = pose.apply(glm::dvec3{500.0, 0.0, 40.0});
  CHECK_FALSE(press.press(0, pose, touch, 11).has_value());
  CHECK_THROWS_WITH(press.press(2, pose, touch, 11), Catch::Contains("object 2"));
}

TEST_CASE("Touch simulator: a scene whose mesh cannot be loaded is refused, naming the object") {
  Scene scene = load_scene("tiny");
  scene.objects[1].mesh = "/nonexistent/brick.glb";
  CHECK_THROWS_WITH(sim::TouchSimulator(scene), Catch::Contains("brick"));
}
