// sva::Map: the public handle over a shared, immutable PairMap.
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>

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

Map Map::train(const Dataset& data, const TrainOptions& options, TrainReport* report) {
  const TrainParameters params = resolve_train_parameters(data.scene, options);
  return Map(train_pair_map(data, params, report));
}

Map Map::load(const std::filesystem::path& file) { return Map(load_pair_map(file)); }

void Map::save(const std::filesystem::path& file) const { save_pair_map(require(map_), file); }

std::size_t Map::objects() const { return require(map_).objects.size(); }
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
std::vector<std::string> Map::object_names() const {
  std::vector<std::string> names;
  for (const auto& o : require(map_).objects) names.push_back(o.name);
  return names;
}
const PairMap& Map::internal() const { return require(map_); }

std::pair<std::uint32_t, std::uint32_t> PairMap::find(std::uint32_t key) const {
  auto it = std::lower_bound(keys.begin(), keys.end(), key);
  if (it == keys.end() || *it != key) return {0, 0};
  auto i = static_cast<std::size_t>(it - keys.begin());
  return {offsets[i], offsets[i + 1]};
}

}  // namespace sva
