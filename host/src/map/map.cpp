// sva::Map: the public handle over a PairMap (skeleton; training and the file
// format are filled in by map_builder.cpp and map_file.cpp).
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>

#include "map/pair_map.hpp"

namespace sva {

namespace {
const PairMap& require(const std::shared_ptr<const PairMap>& m) {
  if (!m) throw Error("map: the map is empty (not trained or loaded)");
  return *m;
}
}  // namespace

Map Map::train(const Dataset&, const TrainOptions&, TrainReport*) { throw Error("sva train: being built (skeleton)"); }
Map Map::load(const std::filesystem::path& file) { throw Error(file.string() + ": map loading is being built (skeleton)"); }
void Map::save(const std::filesystem::path& file) const { throw Error(file.string() + ": map saving is being built (skeleton)"); }

std::size_t Map::objects() const { return require(map_).objects.size(); }
std::uint32_t Map::classes() const { return require(map_).key_space.n_classes; }
std::size_t Map::entries() const { return require(map_).entry_count(); }
std::size_t Map::keys() const { return require(map_).keys.size(); }
std::size_t Map::readings() const { return require(map_).readings.size(); }
std::size_t Map::bytes() const {
  const PairMap& m = require(map_);
  return m.keys.size() * 4 + m.offsets.size() * 4 + m.entry_a.size() * 4 + m.entry_b.size() * 4 + m.entry_weight.size() * 4 +
         m.readings.size() * (4 + 7 * 4);
}
const std::string& Map::scene_name() const { return require(map_).scene_name; }
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
