#pragma once
// The simulated tactile array (docs/sensor-model.md): an object mesh in an
// Embree scene, the pressure image of a sensor pose as one physical array
// reports it, and the contact controller of the paper's Sec 1.1 that presses
// and re-orients the sensor.
#include <sva/reading.hpp>
#include <sva/scene.hpp>
#include <sva/sim/mesh.hpp>
#include <sva/sim/sensor_errors.hpp>

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

// The pressure image of one sensor pose: what the array reports (the scene's
// error model applied), what the controller may use, and the physics' truth.
struct TactileImage {
  std::vector<float> pressure;       // kPa, row-major, rows along y, as the array reports it
  int contacts = 0;                  // reported elements above the contact threshold
  double mean_contact_kpa = 0.0;     // mean reported pressure over those elements (0 without contact)
  glm::dvec2 contact_centroid{0.0};  // pressure-weighted centroid of those elements, sensor (x, y) mm
  // Truth, never for the controller: the penetration-weighted mean of the
  // outward facet normals under the array (0 if nothing touches the skin).
  glm::dvec3 surface_normal{0.0};
  // Physics shortcut, never for the controller: how far the sensor can move
  // along -normal before any ray (margin included) meets the object, capped at
  // the rays' reach: until then the skin touches nothing.
  double clearance_mm = 0.0;
};

class TactileSensor {
 public:
  // `reach_mm`: how far below the skin the rays look for the surface.
  // `errors` and `instance_seed` make the physical array (sensor_errors.hpp);
  // the defaults are the ideal array.
  TactileSensor(const ObjectGeometry& object, const SensorSpec& sensor, const SkinModel& skin, double reach_mm = 20.0,
                const ErrorModel& errors = {}, std::uint64_t instance_seed = 1);
  // The image at `pose`. `frame_seed` seeds the frame's noise (skin.noise_kpa,
  // errors.noise_kpa); each call with the same seed gives the same noise.
  TactileImage touch(const SensorPose& pose, std::uint64_t frame_seed = 0) const;
  // The image of the array touching nothing (offsets and noise only).
  TactileImage untouched(std::uint64_t frame_seed) const;
  const SensorSpec& sensor() const { return sensor_; }
  const SkinModel& skin() const { return skin_; }
  const ObjectGeometry& object() const { return object_; }
  const SensorInstance& instance() const { return instance_; }
  double reach_mm() const { return reach_mm_; }

  // Height of the ray origins above the skin: penetrations deeper than this saturate.
  static constexpr double kRayHeadroomMm = 5.0;

 private:
  std::vector<double> spread(std::vector<double> depth, int nx, int ny) const;
  void summarise(TactileImage& img) const;

  const ObjectGeometry& object_;
  SensorSpec sensor_;
  SkinModel skin_;
  double reach_mm_;
  SensorInstance instance_;
  int rays_per_axis_, margin_;
  std::vector<double> kernel_;
};

struct ControllerSettings {
  int max_iterations = 60;            // controller iterations after the first contact
  bool reorient = true;               // align the normal to the contact (off for letters2d)
  bool recenter = true;               // bring the contact centroid under the array centre
  double pressure_tolerance = 0.04;   // |mean - target| <= tolerance * target
  double normal_tolerance_deg = 2.0;  // tilt of the plane fitted to the image
  double turn_gain = 1.0;             // fraction of the fitted tilt turned per iteration
  double max_turn_deg = 15.0;         // largest re-orientation per iteration
  double kp = 0.9, kd = 0.2;          // PD gains on the pressure error, in units of 1/stiffness
  double max_step_mm = 1.0;           // largest press or retract per iteration
  double approach_step_mm = 0.1;      // guarded move: advance per frame until the threshold is crossed
  double max_approach_mm = 13.0;      // guarded move: give up (no contact) after this travel
};

// The surface under the array as the controller sees it: the outward normal,
// in the sensor frame (x, y, normal), of the plane fitted to the contact points
// of a reported image at the depths its pressures give (docs/sensor-model.md).
// (0, 0, 1) when fewer than two elements are in contact.
glm::dvec3 fit_contact_plane(const std::vector<float>& pressure, const SensorSpec& sensor, const SkinModel& skin);

// The sensor as it settled, with the truth the reading itself does not carry.
struct Contact {
  Reading reading;                 // the true sensor pose and the array's reported image
  glm::dvec3 surface_normal{0.0};  // true outward surface normal under the array (0 without contact)
};

// Runs the contact controller from `start`: a guarded move along -normal until
// the array reports contact, then press / re-orient / re-centre until it
// converges or runs out of iterations. It steers only by the reported images
// (docs/sensor-model.md). `noise_seed` makes the frames' noise reproducible.
Contact press(const TactileSensor& sensor, SensorPose start, const ControllerSettings& settings,
              std::uint64_t noise_seed);

}  // namespace sva::sim
