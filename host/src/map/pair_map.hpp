#pragma once
// The SVA pair map (paper Sec 3): for every object, every pair of its training
// readings whose distance is in range, stored once as (a, b) with a < b under
// every key (class a, class b, distance bin) with non-zero weight; the other
// order is found through the reversed keys (map/pair_keys.hpp). Laid out for the GPU:
// sorted keys with CSR offsets, structure of arrays, compact types.
//
// This header is the contract between the map builder (appearance issue) and
// the recognizer backends (CPU reference and Vulkan). Both read these arrays
// directly.
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "appearance/appearance_baseline.hpp"
#include "appearance/appearance_model.hpp"
#include "calibration/calibration.hpp"
#include "map/pair_keys.hpp"

namespace sva {

struct MapObject {
  std::string name;
  Symmetry symmetry;
  double inertial_radius_mm = 40.0;
};

// One row per training reading that entered the map (object frame, mm).
struct MapReadings {
  std::vector<std::uint32_t> object;
  std::vector<float> px, py, pz;  // contact position
  std::vector<float> nx, ny, nz;  // unit surface normal
  std::vector<float> norm_conf;   // Algorithm 1
  std::size_t size() const { return object.size(); }
  void push_back(std::uint32_t o, const glm::dvec3& position, const glm::dvec3& normal, float conf) {
    object.push_back(o);
    px.push_back(static_cast<float>(position.x));
    py.push_back(static_cast<float>(position.y));
    pz.push_back(static_cast<float>(position.z));
    nx.push_back(static_cast<float>(normal.x));
    ny.push_back(static_cast<float>(normal.y));
    nz.push_back(static_cast<float>(normal.z));
    norm_conf.push_back(conf);
  }
};

struct PairMap {
  // Compatibility with the data it was trained on (recognizer, evaluation).
  std::string scene_name;
  PoseSpaceSpec pose_space;
  std::uint64_t scene_hash = 0;  // FNV-1a 64 of the dataset's scene JSON, mesh paths reduced to file names
  std::uint64_t train_seed = 0;
  double ambiguity = 0.0;  // A: mean number of soft classes per training reading (Sec 1)

  AppearanceModel appearance;  // descriptor, medoids, psi, T_a: classifies new readings
  DistanceBins distance;       // Eq 13 binning
  PairKeySpace key_space;
  std::vector<MapObject> objects;
  MapReadings readings;
  AppearanceBaseline baseline;  // appearance-only recognition of [15] (the paper's comparison)
  Calibration calibration;      // how far to trust the evidence; "none of these" (calibration/calibration.hpp)
  // Each object's surface (format 9: sva::ObjectSurface), one per object, or none (the verify stage then reads the
  // training contacts).
  std::vector<ObjectSurface> surfaces;

  // CSR over sorted keys: entries of keys[i] are [offsets[i], offsets[i+1]).
  std::vector<std::uint32_t> keys;     // strictly increasing
  std::vector<std::uint32_t> offsets;  // keys.size() + 1
  // Entries, structure of arrays, sorted by (reading_a, reading_b) within a
  // key (the recognizer finds a pair under other keys by binary search): the
  // pair (reading_a < reading_b) and
  // its weight under this key: product of the soft class weights of a and b
  // and the distance-bin weight (Eq 15 with uniform class priors).
  std::vector<std::uint32_t> entry_a;
  std::vector<std::uint32_t> entry_b;
  std::vector<float> entry_weight;

  std::size_t entry_count() const { return entry_a.size(); }
  // The reading count from which the fine pose and the surface check run: the calibration's, or its pose space's
  // default (Calibration::fine_pose_start).
  std::uint32_t fine_pose_from() const {
    return Calibration::fine_pose_start(calibration.fine_pose_from, pose_space.kind == PoseSpaceSpec::Kind::planar);
  }
  // Index range of a key's entries; {0, 0} when the key is absent.
  std::pair<std::uint32_t, std::uint32_t> find(std::uint32_t key) const;
};

}  // namespace sva
