#pragma once
// The SVA pair map (paper Sec 3) as a public, opaque, cheap-to-copy handle:
// train it from a dataset, save it, load it. The layout itself (PairMap) is
// private to the engine; see docs/map-format.md for the file format.
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>
#include <sva/reading.hpp>

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

struct TrainOptions {
  // Unset values come from the dataset's scene (Scene::appearance).
  std::optional<std::string> descriptor;  // "mn" or "mnti"
  std::optional<int> clusters;            // n_C
  std::optional<int> dist_bins;           // Eq 13 bin count
  std::optional<double> dist_min_mm;
  std::optional<double> dist_max_mm;
  std::uint64_t seed = 1;  // PAM initialisation
  unsigned threads = 0;    // 0 = all cores (env SVA_THREADS); results do not depend on it
  bool progress = false;   // show progress on stderr
};

// What training did, for the CLI summary.
struct TrainReport {
  std::size_t readings_used = 0;
  std::size_t skipped_not_converged = 0;
  std::size_t skipped_undescribable = 0;  // all-zero image or nothing above the contact threshold
  double clustering_seconds = 0.0;        // wall clock
  double map_build_seconds = 0.0;
  double clustering_cpu_seconds = 0.0;  // process CPU time, all threads (meaningful on a loaded machine)
  double map_build_cpu_seconds = 0.0;
  double clustering_loss = 0.0;  // PAM loss: sum of (1 - affinity) to the medoid
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
  std::vector<std::string> object_names() const;
  // The tactile array the map was trained with: readings must have its rows x cols image.
  const SensorSpec& sensor() const;

  // The engine's private view (host/src/map/pair_map.hpp).
  const PairMap& internal() const;
  std::shared_ptr<const PairMap> shared() const { return map_; }
  explicit Map(std::shared_ptr<const PairMap> map) : map_(std::move(map)) {}

 private:
  std::shared_ptr<const PairMap> map_;
};

}  // namespace sva
