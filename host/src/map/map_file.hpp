#pragma once
// The map file (docs/map-format.md): binary_file container, magic "SVAMAP01".
// The loader validates every size, index and value before the map is used.
#include <filesystem>
#include <memory>
#include <string>

#include "map/pair_map.hpp"

namespace sva {

inline constexpr char kMapMagic[] = "SVAMAP01";
inline constexpr std::uint32_t kMapVersion = 1;

void save_pair_map(const PairMap& map, const std::filesystem::path& file);
std::shared_ptr<PairMap> load_pair_map(const std::filesystem::path& file);
// Throws sva::Error naming `origin` and the first fault found.
void validate_pair_map(const PairMap& map, const std::string& origin);

}  // namespace sva
