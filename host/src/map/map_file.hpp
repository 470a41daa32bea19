#pragma once
// The map file (docs/map-format.md): binary_file container, magic "SVAMAP01".
// The loader validates every size, index and value before the map is used.
#include <filesystem>
#include <memory>
#include <string>

#include "map/pair_map.hpp"

namespace sva {

inline constexpr char kMapMagic[] = "SVAMAP01";
// Version 10: the light estimates' calibration (calibration.hpp, LightCalibration; older maps: none).
// Version 9: the objects' surfaces (sva::ObjectSurface; older maps: none).
// Version 8: the fine pose's start (calibration.hpp).
// Version 7: the calibration's top label (calibration.hpp; older maps: the identity).
// Version 6: the "none of these" model may read this build's four features (calibration.hpp; version 4-5 models
// keep their three); version 5 adds the surface check's weight;
// version 4 adds the calibration (calibration/calibration.hpp; older maps load with its default); version 3
// adds a point of each symmetry axis; version 2 stores each
// unordered training pair once (entry_a < entry_b); version 1 stored both
// orders, and loads by dropping the second order.
inline constexpr std::uint32_t kMapVersion = 10;
inline constexpr std::uint32_t kMapOldestVersion = 1;

void save_pair_map(const PairMap& map, const std::filesystem::path& file);
// The same layout under any version number and without validation: the
// loader's tests write older and broken files with it.
void write_pair_map(const PairMap& map, const std::filesystem::path& file, std::uint32_t version);
std::shared_ptr<PairMap> load_pair_map(const std::filesystem::path& file);
// Throws sva::Error naming `origin` and the first fault found.
void validate_pair_map(const PairMap& map, const std::string& origin);
// Version 1's ordered pairs as version 2's unordered ones: keeps the entries
// with entry_a < entry_b (the other order is the same pair, reversed).
void keep_one_order(PairMap& map);

}  // namespace sva
