#include <sva/error.hpp>
#include <sva/sim/mesh.hpp>
#include <sva/sim/sensor_errors.hpp>
#include <sva/sim/tactile_sensor.hpp>
#include <sva/sim/touch_simulator.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>

namespace sva::sim {

struct TouchSimulator::World {
  Scene scene;
  std::vector<std::unique_ptr<ObjectGeometry>> geometry;
  std::vector<std::unique_ptr<TactileSensor>> sensors;
};

TouchSimulator::TouchSimulator(const Scene& scene) : world_(std::make_unique<World>()) {
  world_->scene = scene;
  const double reach = scene.protocol.approach_mm + 10.0;  // as `sva simulate`'s sensors
  for (const auto& o : scene.objects) {
    try {
      world_->geometry.push_back(std::make_unique<ObjectGeometry>(load_object_mesh(o)));
    } catch (const Error& e) {
      throw Error("object \"" + o.name + "\" has no usable mesh: " + e.what());
    }
    world_->sensors.push_back(std::make_unique<TactileSensor>(*world_->geometry.back(), scene.sensor, scene.skin, reach,
                                                              scene.errors, scene.errors.test_sensor));
  }
}

TouchSimulator::~TouchSimulator() = default;
TouchSimulator::TouchSimulator(TouchSimulator&&) noexcept = default;
TouchSimulator& TouchSimulator::operator=(TouchSimulator&&) noexcept = default;

std::optional<Reading> TouchSimulator::press(std::uint32_t object, const RigidPose& object_pose,
                                             const CandidateTouch& touch, std::uint64_t seed) const {
  const World& w = *world_;
  if (object >= w.sensors.size())
    throw Error("touch simulator: object " + std::to_string(object) + " is not in the scene's " +
                std::to_string(w.sensors.size()) + " objects");
  const RigidPose to_object = object_pose.inverse();
  const glm::dvec3 n = -glm::normalize(to_object.rotate(touch.approach));
  const glm::dvec3 t1 = glm::normalize(glm::cross(std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0), n));
  const glm::dvec3 t2 = glm::cross(n, t1);
  util::Rng rng(seed, 0x5e55);
  const double psi = 2.0 * std::numbers::pi * rng.uniform();
  SensorPose start;
  start.normal = n;
  start.x_axis = pmath::cos(psi) * t1 + pmath::sin(psi) * t2;
  start.position = to_object.apply(touch.position) + w.scene.protocol.approach_mm * n;
  const TactileSensor& sensor = *w.sensors[object];
  ControllerSettings cs;
  cs.max_iterations = w.scene.protocol.max_iterations;
  cs.max_approach_mm = sensor.reach_mm();
  if (w.scene.protocol.kind == "letters2d") cs.reorient = cs.recenter = false;  // pressed flat, as simulated
  const Contact c = sim::press(sensor, start, cs, util::splitmix64(rng.next()));
  if (c.reading.status != ControllerStatus::converged) return std::nullopt;
  Reading r = c.reading;
  report_pose(w.scene.errors, util::splitmix64(rng.next()), r.position, r.normal, r.x_axis);
  r.position = object_pose.apply(r.position);
  r.normal = object_pose.rotate(r.normal);
  r.x_axis = object_pose.rotate(r.x_axis);
  return r;
}

}  // namespace sva::sim
