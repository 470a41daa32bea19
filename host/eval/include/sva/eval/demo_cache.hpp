#pragma once
// The demo's work folder (`sva demo --work DIR`): per scene, DIR/data/<scene>/{train,test}.svad and map.svam, so
// that a second run starts at the evaluation. Datasets are reused only when they were made from the same scene
// (the same JSON, mesh paths included), the same seed and the same reading counts; the map only beside reused
// datasets and only when it was trained from their scene (Map::made_from).
#include <sva/dataset.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace sva::eval {

struct DemoCache {
  std::filesystem::path dir;  // DIR/data/<scene>
  std::filesystem::path train_file, test_file, map_file;

  DemoCache(const std::filesystem::path& work, const Scene& scene);
};

struct CachedDatasets {
  std::optional<Dataset> train, test;  // both set when the cache is reused
  std::string why_not;                 // "" when reused or when nothing is cached; else why it is not used
};

// Reads the cached datasets; `per_object` -1 takes any reading count (the scene's default).
CachedDatasets find_cached_datasets(const DemoCache& cache, const Scene& scene, std::uint64_t seed,
                                    int train_per_object, int test_per_object);

// The cached map, when it was trained from `scene`; `why_not` says why a map that is there is not used.
std::optional<Map> find_cached_map(const DemoCache& cache, const Scene& scene, std::string* why_not = nullptr);

}  // namespace sva::eval
