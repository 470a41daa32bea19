// One sva::Engine on Vulkan: every recognizer made from it shares the device and one uploaded copy of the map,
// and answers as the CPU reference does. Prints the memory it measures (docs/api.md quotes it).
#include <catch2/catch.hpp>

#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>

#include <cstdio>

#include "backends/vulkan/vulkan_engine.hpp"
#include "recognition/trained_map.hpp"
#include "vk_test_support.hpp"

using namespace sva;
using namespace sva::test;

TEST_CASE("GPU engine: two recognizers of one engine hold one map's device memory and answer as the CPU does") {
  const Trained& t = trained();
  EngineOptions eo;
  eo.backend = BackendKind::vulkan;
  std::unique_ptr<Engine> engine;
  try {
    engine = std::make_unique<Engine>(t.map, eo);
  } catch (const Error& e) {
    skip(e.what());
  }
  REQUIRE(engine->backend() == BackendKind::vulkan);
  CHECK(VulkanEngine::alive() == 1);
  BatchRecognizer a(*engine, paper_space(), 1);
  const BatchRecognizer::DeviceMemory one = a.device_memory();
  BatchRecognizer b(*engine, paper_space(), 1);
  const BatchRecognizer::DeviceMemory two = b.device_memory();
  CHECK(VulkanEngine::alive() == 1);
  REQUIRE(one.map_bytes > 0);
  CHECK(two.map_bytes == one.map_bytes);
  // The second recognizer added its work buffers, not a second map.
  CHECK(two.bytes - one.bytes < one.map_bytes);
  std::printf(
      "engine sharing: map %llu B on the device; device total %llu B with one recognizer, %llu B with two "
      "(host map %zu B, shared)\n",
      static_cast<unsigned long long>(one.map_bytes), static_cast<unsigned long long>(one.bytes),
      static_cast<unsigned long long>(two.bytes), t.map.bytes());
  BatchRecognizer cpu(t.map, paper_space(), 1, RecognizerOptions{.backend = BackendKind::cpu});
  const RigidPose truth = random_pose(680, 100.0);
  util::Rng rng(681);
  const std::size_t session = 0;
  for (int i = 0; i < 8; ++i) {
    const Reading r =
        reading_of(t.data.scene.sensor, world_point(t.spec, 1, static_cast<int>(rng.below(70))), truth, rng);
    a.add_readings(std::span(&session, 1), std::span(&r, 1));
    b.add_readings(std::span(&session, 1), std::span(&r, 1));
    cpu.add_readings(std::span(&session, 1), std::span(&r, 1));
  }
  const Estimate ea = a.estimate(0, 3), eb = b.estimate(0, 3), ec = cpu.estimate(0, 3);
  CHECK(ea.object_probability == ec.object_probability);
  CHECK(eb.object_probability == ec.object_probability);
  REQUIRE(ea.hypotheses.size() == ec.hypotheses.size());
  for (std::size_t i = 0; i < ea.hypotheses.size(); ++i) {
    CHECK(ea.hypotheses[i].probability == ec.hypotheses[i].probability);
    CHECK(ea.hypotheses[i].covariance == ec.hypotheses[i].covariance);
  }
  for (int k = 0; k < 3; ++k) CHECK(ea.pose.T[k] == ec.pose.T[k]);
}
