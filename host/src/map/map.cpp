// sva::Map: the public handle over a shared, immutable PairMap.
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>

#include <algorithm>

#include "map/map_access.hpp"
#include "map/map_builder.hpp"
#include "map/map_file.hpp"
#include "map/pair_map.hpp"

namespace sva {

namespace {
const PairMap& require(const std::shared_ptr<const PairMap>& m) {
  if (!m) throw Error("map: the map is empty (not trained or loaded)");
  return *m;
}
template <class T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.size() * sizeof(T);
}
}  // namespace

Map Map::load(const std::filesystem::path& file) { return Map(load_pair_map(file)); }

void Map::save(const std::filesystem::path& file) const { save_pair_map(require(map_), file); }

std::size_t Map::objects() const { return require(map_).objects.size(); }
std::uint32_t Map::fine_pose_from() const { return require(map_).fine_pose_from(); }
std::uint32_t Map::classes() const { return require(map_).key_space.n_classes; }
std::size_t Map::entries() const { return require(map_).entry_count(); }
std::size_t Map::keys() const { return require(map_).keys.size(); }
std::size_t Map::readings() const { return require(map_).readings.size(); }
std::size_t Map::bytes() const {
  const PairMap& m = require(map_);
  const MapReadings& r = m.readings;
  return bytes_of(m.keys) + bytes_of(m.offsets) + bytes_of(m.entry_a) + bytes_of(m.entry_b) + bytes_of(m.entry_weight) +
         bytes_of(r.object) + bytes_of(r.px) + bytes_of(r.py) + bytes_of(r.pz) + bytes_of(r.nx) + bytes_of(r.ny) +
         bytes_of(r.nz) + bytes_of(r.norm_conf) + bytes_of(m.appearance.medoids) + bytes_of(m.appearance.psi) +
         bytes_of(m.baseline.class_given_object);
}
const std::string& Map::scene_name() const { return require(map_).scene_name; }
const SensorSpec& Map::sensor() const { return require(map_).appearance.calibration.sensor; }
const PoseSpaceSpec& Map::pose_space() const { return require(map_).pose_space; }
std::uint64_t Map::scene_hash() const { return require(map_).scene_hash; }
bool Map::made_from(const Scene& scene) const { return require(map_).scene_hash == location_free_scene_hash(scene); }
std::vector<std::string> Map::object_names() const {
  std::vector<std::string> names;
  for (const auto& o : require(map_).objects) names.push_back(o.name);
  return names;
}

MapSummary Map::summary() const {
  const PairMap& m = require(map_);
  MapSummary s;
  s.format_version = kMapVersion;
  s.scene_name = m.scene_name;
  s.planar = m.pose_space.kind == PoseSpaceSpec::Kind::planar;
  s.scene_hash = m.scene_hash;
  s.train_seed = m.train_seed;
  s.descriptor = m.appearance.descriptor == DescriptorKind::mn ? "mn" : "mnti";
  s.descriptor_size = m.appearance.descriptor_size;
  s.prune_ratio = m.appearance.prune_ratio;
  s.classes = m.key_space.n_classes;
  s.ambiguity = m.ambiguity;
  s.distance_bins = m.distance.count;
  s.distance_min_mm = m.distance.min_mm;
  s.distance_max_mm = m.distance.max_mm;
  s.readings = readings();
  s.entries = entries();
  s.keys = keys();
  s.bytes = bytes();
  for (const ObjectSurface& o : m.surfaces) {
    s.surface_objects += 1;
    s.surface_triangles += o.triangles.size();
    s.surface_vertices += o.positions.size();
    s.surface_bytes += bytes_of(o.positions) + bytes_of(o.triangles);
  }
  s.possible_keys = static_cast<std::uint64_t>(m.key_space.n_classes) * m.key_space.n_classes * m.key_space.n_dist_bins;
  if (!m.keys.empty()) {
    std::vector<std::uint32_t> per(m.keys.size());
    for (std::size_t i = 0; i < per.size(); ++i) per[i] = m.offsets[i + 1] - m.offsets[i];
    std::sort(per.begin(), per.end());
    s.entries_per_key_min = per.front();
    s.entries_per_key_median = per[per.size() / 2];
    s.entries_per_key_max = per.back();
  }
  s.objects.resize(m.objects.size());
  for (std::size_t o = 0; o < m.objects.size(); ++o) s.objects[o].name = m.objects[o].name;
  for (auto o : m.readings.object) ++s.objects[o].readings;
  for (auto a : m.entry_a) ++s.objects[m.readings.object[a]].entries;
  std::vector<char> paired(m.readings.size(), 0);
  for (auto a : m.entry_a) paired[a] = 1;
  for (auto b : m.entry_b) paired[b] = 1;
  s.readings_paired = static_cast<std::size_t>(std::count(paired.begin(), paired.end(), 1));
  s.calibration.learned = m.calibration.learned;
  s.calibration.temperature_scale = m.calibration.temperature_scale;
  s.calibration.temperature_power = m.calibration.temperature_power;
  s.calibration.surface_weight = m.calibration.surface_weight;
  s.calibration.top_label_before = m.calibration.top_label[0];
  s.calibration.top_label_after = m.calibration.top_label[1];
  s.calibration.unknown_model = !m.calibration.unknown.empty();
  s.calibration.unknown_from_fit =
      s.calibration.unknown_model && m.calibration.unknown.features == UnknownFeatureSet::evidence_then_fit;
  s.calibration.known_sessions = m.calibration.known_sessions;
  s.calibration.unknown_sessions = m.calibration.unknown_sessions;
  s.calibration.session_readings = m.calibration.session_readings;
  s.calibration.fine_pose_from = fine_pose_from();
  const LightCalibration& light = m.calibration.light;
  s.calibration.light_from = light.from;
  s.calibration.light_temperature_scale = light.temperature_scale;
  s.calibration.light_temperature_power = light.temperature_power;
  s.calibration.light_top_label = light.top_label;
  s.calibration.light_unknown_model = !light.unknown.empty();
  return s;
}

const PairMap& MapAccess::pair_map(const Map& map) { return require(map.map_); }

std::pair<std::uint32_t, std::uint32_t> PairMap::find(std::uint32_t key) const {
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  if (it == keys.end() || *it != key) return {0, 0};
  auto i = static_cast<std::size_t>(it - keys.begin());
  return {offsets[i], offsets[i + 1]};
}

}  // namespace sva
