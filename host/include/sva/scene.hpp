#pragma once
// A scene: the objects, the sensor, the pose space, the appearance model
// defaults and the data-collection protocol. Scenes are JSON files; the
// built-in ones live in assets/scenes/ (see docs/scene-format.md).
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>
#include <sva/reading.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sva {

struct SceneObject {
  std::string name;
  std::filesystem::path mesh;  // absolute after loading (relative paths resolve against the scene file)
  double size_mm = 80.0;       // largest bounding-box dimension after scaling; <= 0 keeps the mesh's units (mm)
  bool center = true;          // move the bounding-box centre to the origin
  Symmetry symmetry;
  std::string family;  // a family of look-alikes it belongs to (eval orders its confusions by it); "" none
  double inertial_radius_mm = 40.0;  // sphere radius of the inertial distance metric
};

// The compliant skin and its calibration (docs/sensor-model.md).
struct SkinModel {
  double stiffness_kpa_per_mm = 100.0;  // pressure per mm of penetration
  double spread_mm = 0.6;               // std-dev of the elastic layer's spread
  int rays_per_axis = 3;                // rays per element = rays_per_axis^2
  double noise_kpa = 0.0;               // std-dev of additive Gaussian noise
  double contact_threshold_kpa = 2.0;   // an element is in contact above this
  double target_pressure_kpa = 20.0;    // controller target for the mean pressure of contacting elements
};

// What separates a reading from the truth: the arm's pose errors and one
// physical sensor's imperfections (docs/sensor-model.md, "Error model"). All
// zero (the default, and a scene without an "errors" block) is the ideal world.
struct ErrorModel {
  double position_sigma_mm = 0.0;   // arm: Gaussian per axis on the reported sensor position, per reading
  double normal_sigma_deg = 0.0;    // arm: Gaussian per axis of the rotation vector turning the reported frame
  double gain_spread = 0.0;         // per-element gain std-dev (fraction of 1), fixed for one sensor instance
  double offset_kpa = 0.0;          // per-element offset std-dev, fixed for one sensor instance
  double noise_kpa = 0.0;           // per element per frame (adds in quadrature to skin.noise_kpa)
  double full_scale_kpa = 0.0;      // an element saturates here (0: never)
  double crosstalk = 0.0;           // fraction of an element's pressure read by each of its 4 edge neighbours
  double crosstalk_diagonal = 0.0;  // ... and by each of its 4 corner neighbours
  std::uint32_t train_sensor = 1;   // sensor instance seed of the training readings
  std::uint32_t test_sensor = 1;    // ... and of the test readings (differ: two physical sensors)

  bool arm_ideal() const { return position_sigma_mm == 0.0 && normal_sigma_deg == 0.0; }
};

struct AppearanceSpec {
  std::string descriptor = "mnti";  // "mn" or "mnti"
  int clusters = 25;
  int dist_bins = 40;
  double dist_min_mm = 30.0;
  double dist_max_mm = 160.0;
  // Training readings per object that enter the map's pairs (0: all). The map's entries grow with the square of
  // the readings that pair; every training reading is kept as a contact of the object's surface, which the fine
  // pose, the surface check, "none of these" and the touch planner read. A scene of near-twins touches each object
  // more than it pairs (lookalikes: 1,200 readings, 300 of them paired; docs/recognition.md, "Surface check").
  int pair_readings = 0;
};

struct ProtocolSpec {
  std::string kind = "paper3d";  // "paper3d" or "letters2d"
  int train_per_object = 1000;   // paper3d; letters2d uses one reading per grid pose
  int test_per_object = 100;
  double approach_mm = 3.0;  // paper3d: start this far along the normal
  double tilt_deg = 10.0;    // paper3d: random tilt of the initial sensor normal
  int grid = 4;              // letters2d: grid x grid positions
  double grid_spacing_mm = 6.8;
  int orientations = 12;
  int max_iterations = 60;  // contact controller budget
};

struct Scene {
  std::string name;
  std::filesystem::path file;  // where it was loaded from (empty for in-memory scenes)
  std::vector<SceneObject> objects;
  SensorSpec sensor;
  SkinModel skin;
  ErrorModel errors;
  PoseSpaceSpec pose_space;
  AppearanceSpec appearance;
  ProtocolSpec protocol;
};

// Parse a scene from JSON text; `origin` names the source in error messages and
// is the directory relative mesh paths resolve against.
Scene parse_scene(const std::string& json_text, const std::filesystem::path& origin);
// Load a scene file, or a built-in scene by name (builtin_scene_names()).
Scene load_scene(const std::string& name_or_file);
// The names of the built-in scenes (assets/scenes/NAME.json).
const std::vector<std::string>& builtin_scene_names();
// The scene serialised back to JSON (mesh paths absolute).
std::string scene_to_json(const Scene& scene);
// Directory of the built-in assets: env SVA_ASSETS when set, else the directory an embedding registered with
// set_assets_dir (the Python package registers the copy inside its wheel), else the source tree's, else the
// installed one (share/sva/assets).
std::filesystem::path assets_dir();
void set_assets_dir(const std::filesystem::path& dir);

}  // namespace sva
