#include <sva/eval/demo_cache.hpp>

#include <sva/error.hpp>

#include <system_error>

namespace sva::eval {

namespace {

// A dataset made from this scene, seed and reading count (per object; -1: any).
bool matches(const Dataset& d, const Scene& scene, std::uint64_t seed, int per_object) {
  if (d.seed != seed || scene_to_json(d.scene) != scene_to_json(scene)) return false;
  if (per_object < 0) return true;
  return d.samples.size() == static_cast<std::size_t>(per_object) * scene.objects.size();
}

}  // namespace

DemoCache::DemoCache(const std::filesystem::path& work, const Scene& scene)
    : dir(work / "data" / scene.name),
      train_file(dir / "train.svad"),
      test_file(dir / "test.svad"),
      map_file(dir / "map.svam") {}

CachedDatasets find_cached_datasets(const DemoCache& cache, const Scene& scene, std::uint64_t seed,
                                    int train_per_object, int test_per_object) {
  CachedDatasets out;
  std::error_code ec;
  if (!std::filesystem::exists(cache.train_file, ec) || !std::filesystem::exists(cache.test_file, ec)) return out;
  try {
    Dataset train = load_dataset(cache.train_file), test = load_dataset(cache.test_file);
    if (!matches(train, scene, seed, train_per_object) || !matches(test, scene, seed, test_per_object)) {
      out.why_not = "it is for another scene, seed or reading count";
      return out;
    }
    out.train = std::move(train);
    out.test = std::move(test);
  } catch (const Error& e) {
    out.why_not = std::string("it is unusable: ") + e.what();
  }
  return out;
}

std::optional<Map> find_cached_map(const DemoCache& cache, const Scene& scene, std::string* why_not) {
  std::error_code ec;
  if (!std::filesystem::exists(cache.map_file, ec)) return std::nullopt;
  try {
    Map map = Map::load(cache.map_file);
    if (map.made_from(scene)) return map;
    if (why_not) *why_not = "it was trained from another scene";
  } catch (const Error& e) {
    if (why_not) *why_not = std::string("it is unusable: ") + e.what();
  }
  return std::nullopt;
}

}  // namespace sva::eval
