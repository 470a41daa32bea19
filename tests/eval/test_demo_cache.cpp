// The demo's cache (sva/eval/demo_cache.hpp): datasets reused only for the same scene, seed and reading counts, a
// map only when trained from that scene, wherever its meshes lie; anything else says why it is not used.
#include <catch2/catch.hpp>
#include <sva/dataset.hpp>
#include <sva/eval/demo_cache.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>
#include <sva/sim/simulate.hpp>

#include <fstream>

#include "test_support.hpp"

using namespace sva;
using Catch::Contains;

namespace {

sim::SimulatedData tiny_data(std::uint64_t seed) {
  sim::SimulateOptions so;
  so.seed = seed;
  so.train_per_object = 12;
  so.test_per_object = 2;
  return sim::simulate(load_scene("tiny"), so);
}

}  // namespace

TEST_CASE("demo cache: datasets are reused for the same scene, seed and counts only") {
  const Scene scene = load_scene("tiny");
  const eval::DemoCache cache(test::temp_dir("demo-cache-data"), scene);
  eval::CachedDatasets none = eval::find_cached_datasets(cache, scene, 1, 12, 2);
  CHECK_FALSE(none.train);
  CHECK(none.why_not.empty());  // nothing cached is no fault

  const sim::SimulatedData data = tiny_data(1);
  std::filesystem::create_directories(cache.dir);
  save_dataset(data.train, cache.train_file);
  save_dataset(data.test, cache.test_file);
  eval::CachedDatasets same = eval::find_cached_datasets(cache, scene, 1, 12, 2);
  REQUIRE(same.train);
  CHECK(same.train->samples.size() == data.train.samples.size());
  CHECK(same.test->samples.size() == data.test.samples.size());
  CHECK(eval::find_cached_datasets(cache, scene, 1, -1, -1).train);  // any count

  for (auto [seed, train] : {std::pair<std::uint64_t, int>{2, 12}, {1, 13}}) {
    eval::CachedDatasets other = eval::find_cached_datasets(cache, scene, seed, train, 2);
    CHECK_FALSE(other.train);
    CHECK_THAT(other.why_not, Contains("another scene, seed or reading count"));
  }
  std::ofstream(cache.test_file, std::ios::trunc) << "not a dataset";
  eval::CachedDatasets broken = eval::find_cached_datasets(cache, scene, 1, 12, 2);
  CHECK_FALSE(broken.train);
  CHECK_THAT(broken.why_not, Contains("unusable") && Contains("test.svad"));
}

TEST_CASE("demo cache: the map is reused when trained from the scene, wherever its meshes lie") {
  const Scene scene = load_scene("tiny");
  const eval::DemoCache cache(test::temp_dir("demo-cache-map"), scene);
  CHECK_FALSE(eval::find_cached_map(cache, scene));
  TrainOptions to;
  to.clusters = 3;
  const Map map = Map::train(tiny_data(1).train, to);
  std::filesystem::create_directories(cache.dir);
  map.save(cache.map_file);

  const std::optional<Map> found = eval::find_cached_map(cache, scene);
  REQUIRE(found);
  CHECK(found->entries() == map.entries());
  Scene moved = scene;  // the same meshes in another checkout
  for (auto& o : moved.objects) o.mesh = std::filesystem::path("/elsewhere/objects") / o.mesh.filename();
  CHECK(map.made_from(moved));
  CHECK(eval::find_cached_map(cache, moved));

  Scene other = scene;
  other.objects[0].name = "renamed";
  std::string why_not;
  CHECK_FALSE(map.made_from(other));
  CHECK_FALSE(eval::find_cached_map(cache, other, &why_not));
  CHECK_THAT(why_not, Contains("another scene"));
  std::ofstream(cache.map_file, std::ios::trunc) << "not a map";
  CHECK_FALSE(eval::find_cached_map(cache, scene, &why_not));
  CHECK_THAT(why_not, Contains("unusable") && Contains("map.svam"));
}
