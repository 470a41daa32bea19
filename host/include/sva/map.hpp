#pragma once
// The SVA pair map (paper Sec 3) as a public, opaque, cheap-to-copy handle:
// train it from a dataset, save it, load it. The layout itself (PairMap) is
// private to the engine; see docs/map-format.md for the file format.
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>
#include <sva/reading.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sva {

struct PairMap;
struct Dataset;  // sva/dataset.hpp
struct Scene;    // sva/scene.hpp

// One object's surface: its mesh in millimetres, in the object's own frame (the frame of its training readings: the
// simulator's mesh after the scene's scale and centring), triangles counter-clockwise seen from outside. A map
// trained with them carries them (format 9), and the estimate's verify stage weighs every reading against them
// (docs/recognition.md, "The measurement model"); sva::sim::object_surfaces loads them from a scene's meshes.
struct ObjectSurface {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;  // indices into positions
};

struct TrainOptions {
  // Unset values come from the dataset's scene (Scene::appearance).
  std::optional<std::string> descriptor;  // "mn" or "mnti"
  std::optional<int> clusters;            // n_C
  std::optional<int> dist_bins;           // Eq 13 bin count
  std::optional<double> dist_min_mm;
  std::optional<double> dist_max_mm;
  // Training readings per object that enter the pairs (0: all), drawn at random (seeded by `seed`) from each
  // object's usable readings; the rest are kept as surface contacts only (Scene::appearance.pair_readings).
  std::optional<std::size_t> pair_readings;
  std::uint64_t seed = 1;  // PAM initialisation and the draw of the paired readings (pair_readings)
  unsigned threads = 0;    // 0 = all cores (env SVA_THREADS); results do not depend on it
  bool progress = false;   // show progress on stderr
  // Calibration (docs/recognition.md, "Calibration"): learn how far to trust the evidence, and when to say "none
  // of these", from training readings the map never sees. A fifth of the objects (three or more objects) and
  // `calibration_held_out` of every other object's readings are held out, a calibration map is trained on the
  // rest, and sessions on the held-out readings are run on it. The map itself is then trained on every reading.
  // Off (or fewer than two objects): the documented default temperature, no "none of these".
  bool calibrate = true;
  double calibration_held_out = 0.1;      // in (0, 0.5]
  std::size_t calibration_sessions = 60;  // on known objects (half as many on held-out objects), 10 to 100000
  std::size_t calibration_readings = 12;  // per session, 2 to 1000
  // The reading count from which the fine pose and the surface check run (3 to 1000; unset: 6, 3 in a planar pose
  // space). The map keeps it and its calibration is learned with it (docs/recognition.md, "Fine pose"): 4 names
  // distinct objects right sooner, while twins' probabilities are trusted less (docs/evaluation.md).
  std::optional<std::uint32_t> fine_pose_from;
  // The objects' surfaces, one per object of the dataset's scene in its order, or none: a map without surfaces
  // (trained from a real sensor's recordings, say) verifies its leading objects against the training contacts.
  std::vector<ObjectSurface> surfaces;

  // The options as given, before the scene's defaults fill the unset ones: throws sva::Error naming the option,
  // its value and the fault, after `context` (the caller: "sva train", "sva.train"). Map::train checks them too
  // (and the scene's defaults); a caller checks early to fail before loading a dataset.
  void validate(const std::string& context = "train options") const;
};

// What training did, for the CLI summary.
struct TrainReport {
  std::size_t readings_used = 0;
  std::size_t readings_paired = 0;  // of them, those in the map's pairs (TrainOptions::pair_readings); the rest are
                                    // surface contacts only
  std::size_t skipped_not_converged = 0;
  std::size_t skipped_undescribable = 0;  // all-zero image or nothing above the contact threshold
  double clustering_seconds = 0.0;        // wall clock
  double map_build_seconds = 0.0;
  double clustering_cpu_seconds = 0.0;  // process CPU time, all threads (meaningful on a loaded machine)
  double map_build_cpu_seconds = 0.0;
  double clustering_loss = 0.0;      // PAM loss: sum of (1 - affinity) to the medoid
  double calibration_seconds = 0.0;  // wall clock: the calibration map and its sessions
  std::string calibration_note;      // why the map holds the default calibration ("" when it was learned)
};

// What a map holds, as `sva inspect` and `sva train` print it.
struct MapSummary {
  std::uint32_t format_version = 0;  // of the map file this build writes (docs/map-format.md)
  std::string scene_name;
  bool planar = false;  // pose space: planar (x, y, yaw) or spatial
  std::uint64_t scene_hash = 0;
  std::uint64_t train_seed = 0;
  std::string descriptor;  // "mn" or "mnti"
  std::uint32_t descriptor_size = 0;
  double prune_ratio = 0.0;  // T_a
  std::uint32_t classes = 0;
  double ambiguity = 0.0;  // classes per reading
  std::uint32_t distance_bins = 0;
  double distance_min_mm = 0.0, distance_max_mm = 0.0;
  std::size_t readings = 0, entries = 0, keys = 0, bytes = 0;  // bytes: the pairs, readings and appearance model
  // The objects' surfaces (format 9): objects with one (0: none, the verify stage reads the training contacts), their
  // triangles and vertices, and their bytes, apart from `bytes`.
  std::size_t surface_objects = 0, surface_triangles = 0, surface_vertices = 0, surface_bytes = 0;
  std::size_t readings_paired = 0;  // readings in at least one pair; the rest are surface contacts only
  std::uint64_t possible_keys = 0;  // classes^2 x distance bins
  std::uint32_t entries_per_key_min = 0, entries_per_key_median = 0, entries_per_key_max = 0;  // 0 without keys
  struct Object {
    std::string name;
    std::size_t readings = 0, entries = 0;  // entries: pairs whose first reading is this object's
  };
  std::vector<Object> objects;
  // The calibration (docs/recognition.md, "Calibration"): learned, or the default of older maps and of training
  // without it. tau(n) = temperature_scale (n - 1)^-temperature_power.
  struct Calibration {
    bool learned = false;
    double temperature_scale = 0.0, temperature_power = 0.0;
    double surface_weight = 0.0;  // the surface check's bits per bit of the posterior (docs/recognition.md)
    // The top object's probability recalibrated, logit p' = a + b logit p, as {a, b}: before the fine pose exists
    // and from it on ({0, 1}: as the temperature left it; maps of format 1-6).
    std::array<double, 2> top_label_before{0.0, 1.0}, top_label_after{0.0, 1.0};
    bool unknown_model = false;     // the map can say "none of these"
    bool unknown_from_fit = false;  // ... from the fine pose's fit once it exists (format 6); else the evidence alone
    std::uint32_t known_sessions = 0, unknown_sessions = 0, session_readings = 0;
    std::uint32_t fine_pose_from = 0;  // readings from which the fine pose and the surface check run
    // Light estimates' own calibration from `light_from` readings on (format 10; 0: none, they read the evidence
    // regime extrapolated): its temperature, top label and "none of these" from the evidence alone.
    std::uint32_t light_from = 0;
    double light_temperature_scale = 0.0, light_temperature_power = 0.0;
    std::array<double, 2> light_top_label{0.0, 1.0};
    bool light_unknown_model = false;
  } calibration;
};

class Map {
 public:
  Map() = default;

  static Map train(const Dataset& data, const TrainOptions& options = {}, TrainReport* report = nullptr);
  static Map load(const std::filesystem::path& file);
  void save(const std::filesystem::path& file) const;

  bool empty() const { return !map_; }
  std::size_t objects() const;
  std::uint32_t classes() const;
  std::size_t entries() const;
  std::size_t keys() const;
  std::size_t readings() const;
  std::size_t bytes() const;  // in-memory size of the map's arrays

  // Compatibility information for the recognizer and the evaluation.
  const std::string& scene_name() const;
  const PoseSpaceSpec& pose_space() const;
  std::uint64_t scene_hash() const;  // FNV-1a of the dataset's scene JSON, mesh paths reduced to file names
  // Whether the map was trained on readings of `scene` (the same scene hash): a cached map is reused only then.
  bool made_from(const Scene& scene) const;
  std::vector<std::string> object_names() const;
  // The reading count from which the fine pose and the surface check run (TrainOptions::fine_pose_from; maps of
  // format 1-7: 6, planar 3). A recognizer on the map starts there, as its calibration was learned.
  std::uint32_t fine_pose_from() const;
  // The tactile array the map was trained with: readings must have its rows x cols image.
  const SensorSpec& sensor() const;

  MapSummary summary() const;

 private:
  // The engine's view of the layout (host/src/map/map_access.hpp); nothing public reaches it.
  friend struct MapAccess;
  explicit Map(std::shared_ptr<const PairMap> map) : map_(std::move(map)) {}
  std::shared_ptr<const PairMap> map_;
};

}  // namespace sva
