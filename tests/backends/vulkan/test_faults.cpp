// GPU faults, injected on any device (lavapipe included) through backends/vulkan/faults.hpp: device memory that runs
// out (the map: a clear error, and the CPU reference under auto; a batch's tables: split further, same answers), a
// device that is lost mid-session (sva::DeviceLost, then the session rebuilt from its readings on a new engine),
// a device without a feature the engine needs (an error naming it), and a named driver that does not load (an error
// naming it and how to see why).
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/vulkan_engine.hpp"
#include "map/map_access.hpp"
#include "recognition/fixture.hpp"
#include "recognition/trained_map.hpp"
#include "vk_test_support.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// Every injected fault is cleared when a test ends, passed or not.
struct FaultsCleared {
  ~FaultsCleared() {
    vk::faults::set_memory_budget(0);
    vk::faults::clear_device_loss();
    vk::faults::set_missing_feature("");
  }
};

// The name of the Vulkan device, so that auto tries it even when it is a software one; skips without a device.
std::string device_name_or_skip() {
  try {
    return probe_vulkan_device().name;
  } catch (const Error& e) {
    skip(e.what());
  }
}

std::vector<Reading> readings_of_object(std::uint32_t object, int n, std::uint64_t seed) {
  return readings_at(object, random_pose(seed, 100.0), util::Rng(seed + 1), n);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("GPU faults: a map past the device memory is a clear error on vulkan and the CPU reference under auto") {
  FaultsCleared cleared;
  const std::string device = device_name_or_skip();
  const Trained& t = trained();
  const std::size_t need = VulkanEngine::map_device_bytes(MapAccess::pair_map(t.map));
  REQUIRE(need > 4096);
  vk::faults::set_memory_budget(need / 2);
  try {
    Engine engine(t.map, {.backend = BackendKind::vulkan, .vulkan_device = device});
    FAIL("the map was uploaded past the memory budget");
  } catch (const Interrupted&) {
    throw;
  } catch (const Error& e) {
    INFO(e.what());
    CHECK(contains(e.what(), "the map needs " + std::to_string(need) + " bytes of GPU memory"));
    CHECK(contains(e.what(), "VK_ERROR_OUT_OF_DEVICE_MEMORY"));
    CHECK(contains(e.what(), device));
  }
  const Engine fallback(t.map, {.backend = BackendKind::automatic, .vulkan_device = device});
  CHECK(fallback.backend() == BackendKind::cpu);
  CHECK(contains(fallback.fallback_reason(), "does not fit"));
  // The CPU reference answers as it always does.
  Recognizer rec(fallback, paper_space());
  for (const Reading& r : readings_of_object(1, 6, 700)) rec.add_reading(r);
  CHECK(rec.estimate().object == 1);
}

TEST_CASE("GPU faults: a batch whose tables do not fit is split further and votes exactly as the CPU reference") {
  FaultsCleared cleared;
  WorldSpec spec;
  auto w = make_world(spec);
  PoseSpace space(paper_space(), static_cast<std::uint32_t>(spec.objects));
  // Eight sessions of six readings: the pairs of the last readings in one batch.
  VoteBatch batch;
  std::vector<std::unique_ptr<VoteBackend>> cpu_backends;
  std::vector<std::unique_ptr<BayesFilter>> filters;
  for (int s = 0; s < 8; ++s) {
    const int object = s % spec.objects;
    const RigidPose pose = random_pose(300 + static_cast<std::uint64_t>(s), 150.0);
    cpu_backends.push_back(make_cpu_vote_backend(*w.map, space, {}));
    filters.push_back(std::make_unique<BayesFilter>(*w.map, space, FilterOptions{}, *cpu_backends.back()));
    for (int r = 0; r < 5; ++r)
      filters.back()->add(observe(w.objects[object][static_cast<std::size_t>(r * 7 % spec.points)], pose));
    filters.back()->queue_pairs(observe(w.objects[object][static_cast<std::size_t>(41 % spec.points)], pose),
                                static_cast<std::uint32_t>(s), &batch);
  }
  const std::vector<PairVotes> cpu = make_cpu_vote_backend(*w.map, space, {})->vote(batch);
  VulkanBackendOptions o;
  o.initial_table_slots = 1024;
  std::uint64_t before = 0, after = 0;
  {
    auto gpu = vulkan_backend_or_skip(*w.map, space, {}, o);
    before = gpu->statistics().device_bytes;
    gpu->vote(batch);
    after = gpu->statistics().device_bytes;
  }
  REQUIRE(after > before);
  // Half of what the whole batch needed beyond the map: the batch cannot run in one pass.
  const std::uint64_t budget = before + (after - before) / 2;
  auto gpu = vulkan_backend_or_skip(*w.map, space, {}, o);
  REQUIRE(gpu->statistics().device_bytes == before);
  vk::faults::set_memory_budget(budget);
  const std::vector<PairVotes> split = gpu->vote(batch);
  CHECK(gpu->statistics().device_bytes <= budget);
  REQUIRE(cpu.size() == split.size());
  std::uint64_t votes = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    INFO("pair " << i);
    CHECK(cpu[i].votes == split[i].votes);
    CHECK(cpu[i].keys == split[i].keys);
    CHECK(cpu[i].mass == split[i].mass);
    votes += cpu[i].votes;
  }
  CHECK(votes > 1000);
  std::printf("GPU faults: a batch of %zu pairs needed %llu B beyond the map; run within %llu B by splitting\n",
              batch.pairs.size(), static_cast<unsigned long long>(after - before),
              static_cast<unsigned long long>(budget - before));
}

TEST_CASE("GPU faults: a lost device is reported and the session is rebuilt from its readings on a new engine") {
  FaultsCleared cleared;
  const std::string device = device_name_or_skip();
  const Trained& t = trained();
  const std::vector<Reading> readings = readings_of_object(2, 10, 710);
  auto engine = std::make_unique<Engine>(t.map, EngineOptions{.backend = BackendKind::vulkan, .vulkan_device = device});
  REQUIRE(engine->backend() == BackendKind::vulkan);
  auto rec = std::make_unique<Recognizer>(*engine, paper_space());
  for (int i = 0; i < 4; ++i) rec->add_reading(readings[static_cast<std::size_t>(i)]);
  vk::faults::lose_device_after(0);
  CHECK_THROWS_WITH(rec->add_reading(readings[4]), Catch::Contains("VK_ERROR_DEVICE_LOST"));
  // The session refuses later work (its belief holds part of the lost update); the readings taken so far are intact.
  CHECK_THROWS_AS(rec->add_reading(readings[4]), Error);
  CHECK(rec->reading_count() == 4);
  // The documented recovery: save, a new engine (a new device: the lost one serves no new engine), restore.
  const auto dir = temp_dir("gpu-faults");
  rec->save_session(dir / "lost.svas");
  const Engine fresh(t.map, {.backend = BackendKind::vulkan, .vulkan_device = device});
  CHECK(VulkanEngine::alive() == 2);
  Recognizer rebuilt(fresh, paper_space());
  rebuilt.restore_session(dir / "lost.svas");
  REQUIRE(rebuilt.reading_count() == 4);
  rec.reset();
  engine.reset();
  CHECK(VulkanEngine::alive() == 1);
  for (std::size_t i = 4; i < readings.size(); ++i) rebuilt.add_reading(readings[i]);
  Recognizer cpu(t.map, paper_space(), {.backend = BackendKind::cpu});
  for (const Reading& r : readings) cpu.add_reading(r);
  const Estimate g = rebuilt.estimate(3), c = cpu.estimate(3);
  CHECK(g.readings == readings.size());
  CHECK(g.object_probability == c.object_probability);
  CHECK(g.object == 2);
  for (int k = 0; k < 3; ++k) CHECK(g.pose.T[k] == c.pose.T[k]);
  std::filesystem::remove_all(dir);
}

TEST_CASE("GPU faults: a device without a needed feature is refused with the feature's name") {
  FaultsCleared cleared;
  const std::string device = device_name_or_skip();
  const Trained& t = trained();
  for (const char* feature : {"shaderInt64", "shaderBufferInt64Atomics", "bufferDeviceAddress", "Vulkan 1.2"}) {
    INFO(feature);
    vk::faults::set_missing_feature(feature);
    try {
      Engine engine(t.map, {.backend = BackendKind::vulkan, .vulkan_device = device});
      FAIL("a device without " << feature << " was used");
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(contains(e.what(), std::string("lacks ") + feature));
    }
    const Engine fallback(t.map, {.backend = BackendKind::automatic, .vulkan_device = device});
    CHECK(fallback.backend() == BackendKind::cpu);
    CHECK(contains(fallback.fallback_reason(), feature));
  }
}

TEST_CASE("GPU faults: the CLI names an injected fault and exits non-zero") {
  const std::string device = device_name_or_skip();
  const auto dir = temp_dir("gpu-faults-cli");
  std::string out;
  // The fixture's map and its training data, through sva bench's shortest run on the named device.
  const Trained& t = trained();
  t.map.save(dir / "map.svam");
  save_dataset(t.data, dir / "test.svad");
  const std::string base = "bench --map " + (dir / "map.svam").string() + " --data " + (dir / "test.svad").string() +
                           " --readings 3 --trials 1 --batch 0 --roofline-votes 1024 --backend vulkan --device \"" +
                           device + "\"";
  CHECK(run_sva(base + " --help", &out) == 0);
  setenv("SVA_VK_FAULT_MISSING_FEATURE", "bufferDeviceAddress", 1);
  const int code = run_sva(base, &out);
  unsetenv("SVA_VK_FAULT_MISSING_FEATURE");
  INFO(out);
  CHECK(code != 0);
  CHECK(contains(out, "lacks bufferDeviceAddress"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("a Vulkan driver named by VK_DRIVER_FILES that does not load is an error naming the variable and file") {
  // A bare NVIDIA container's ICD file whose library cannot load (libglvnd missing) left a device check with no
  // Vulkan test run and a message that asked for Mesa (the fifth GPU run, docs/vulkan-backend.md).
  const auto dir = temp_dir("gpu-faults-driver");
  std::string out;
  const Trained& t = trained();
  t.map.save(dir / "map.svam");
  save_dataset(t.data, dir / "test.svad");
  const std::string missing = (dir / "no_such_icd.json").string();
  const char* was = std::getenv("VK_DRIVER_FILES");
  const std::string saved = was ? was : "";
  setenv("VK_DRIVER_FILES", missing.c_str(), 1);
  const int code = run_sva("bench --map " + (dir / "map.svam").string() + " --data " + (dir / "test.svad").string() +
                               " --readings 3 --trials 1 --batch 0 --backend vulkan",
                           &out);
  if (was)
    setenv("VK_DRIVER_FILES", saved.c_str(), 1);
  else
    unsetenv("VK_DRIVER_FILES");
  INFO(out);
  CHECK(code != 0);
  CHECK(contains(out, "no Vulkan device: the Vulkan driver named by VK_DRIVER_FILES=" + missing + " did not load"));
  CHECK(contains(out, "VK_LOADER_DEBUG"));
  std::filesystem::remove_all(dir);
}
