#pragma once
// The simulated tactile array (docs/sensor-model.md): an object mesh in an
// Embree scene, the pressure image of a sensor pose, and the contact
// controller of the paper's Sec 1.1 that presses and re-orients the sensor.
#include <sva/reading.hpp>
#include <sva/scene.hpp>
#include <sva/sim/mesh.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace sva::sim {

// The sensor frame: `position` is the centre of the skin surface, `normal` the
// outward surface normal it is aligned to (the sensor presses along -normal),
// `x_axis` the column direction; rows run along y = normal x x_axis.
struct SensorPose {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 x_axis{1.0, 0.0, 0.0};
};

// One object mesh in an Embree scene (robust build). Thread-safe queries.
// Embree errors become sva::Error.
class ObjectGeometry {
 public:
  explicit ObjectGeometry(Mesh mesh);
  ~ObjectGeometry();
  ObjectGeometry(const ObjectGeometry&) = delete;
  ObjectGeometry& operator=(const ObjectGeometry&) = delete;

  struct Hit {
    bool hit = false;
    double t = 0.0;
    glm::dvec3 normal{0.0};  // unit geometric normal of the triangle hit (mesh winding)
    std::uint32_t triangle = 0;
  };
  Hit intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tnear, double tfar) const;
  // Many parallel rays at once (a coherent stream: much faster than one by one).
  void intersect_parallel(const std::vector<glm::dvec3>& origins, const glm::dvec3& direction, double tfar,
                          std::vector<Hit>& hits) const;
  const Mesh& mesh() const;

  // A point uniformly distributed by area with its outward facet normal.
  // `u0`, `u1`, `u2` are uniform in [0, 1).
  void sample_surface(double u0, double u1, double u2, glm::dvec3& point, glm::dvec3& normal) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The pressure image of one sensor pose, with what the controller needs.
struct TactileImage {
  std::vector<float> pressure;       // kPa, row-major, rows along y
  int contacts = 0;                  // elements above the contact threshold
  double mean_contact_kpa = 0.0;     // mean pressure over those elements (0 without contact)
  glm::dvec2 contact_centroid{0.0};  // pressure-weighted centroid of those elements, sensor (x, y) mm
  // Penetration-weighted mean of the outward facet normals under the array
  // (0 if none): where a passive compliant wrist would settle the sensor.
  glm::dvec3 surface_normal{0.0};
  bool surface_below = false;  // some ray of the array met the object within reach
  double gap_mm = 0.0;         // smallest distance from the skin to the object along -normal (<= 0: touching)
};

class TactileSensor {
 public:
  // `reach_mm`: how far below the skin the rays look for the surface.
  TactileSensor(const ObjectGeometry& object, const SensorSpec& sensor, const SkinModel& skin, double reach_mm = 20.0);
  // The image at `pose`. `noise_seed` seeds the additive noise (skin.noise_kpa);
  // each call with the same seed gives the same noise.
  TactileImage touch(const SensorPose& pose, std::uint64_t noise_seed = 0) const;
  const SensorSpec& sensor() const { return sensor_; }
  const SkinModel& skin() const { return skin_; }
  const ObjectGeometry& object() const { return object_; }

  // Height of the ray origins above the skin: penetrations deeper than this saturate.
  static constexpr double kRayHeadroomMm = 5.0;

 private:
  const ObjectGeometry& object_;
  SensorSpec sensor_;
  SkinModel skin_;
  double reach_mm_;
  int rays_per_axis_, margin_;
  std::vector<double> kernel_;
};

struct ControllerSettings {
  int max_iterations = 60;
  bool reorient = true;               // align the normal to the contact (off for letters2d)
  bool recenter = true;               // bring the contact centroid under the array centre
  double pressure_tolerance = 0.04;   // |mean - target| <= tolerance * target
  double normal_tolerance_deg = 2.0;  // angle between sensor and estimated surface normal
  double turn_gain = 1.0;             // fraction of the estimated misalignment turned per iteration
  double max_turn_deg = 15.0;         // largest re-orientation per iteration
  double kp = 0.9, kd = 0.2;          // PD gains on the pressure error, in units of 1/stiffness
  double max_step_mm = 1.0;           // largest press or retract per iteration
};

// Runs the contact controller from `start` until it converges or runs out of
// iterations. The reading holds the pose and image of the last evaluation;
// its status says whether it converged. `noise_seed` makes noise reproducible.
Reading press(const TactileSensor& sensor, SensorPose start, const ControllerSettings& settings,
              std::uint64_t noise_seed);

}  // namespace sva::sim
