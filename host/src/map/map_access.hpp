#pragma once
// The engine's view of a public Map: its PairMap (map/pair_map.hpp). Map befriends this one struct and hands out
// nothing else, so the layout stays private to sva_core (and to its tests and tools built in this tree).
#include <sva/map.hpp>

#include <memory>

namespace sva {

struct MapAccess {
  // Throws sva::Error when the map is empty.
  static const PairMap& pair_map(const Map& map);
  // The shared layout (null for an empty map): holders that outlive the caller's Map keep it alive.
  static const std::shared_ptr<const PairMap>& shared(const Map& map) { return map.map_; }
  static Map wrap(std::shared_ptr<const PairMap> map) { return Map(std::move(map)); }
};

}  // namespace sva
