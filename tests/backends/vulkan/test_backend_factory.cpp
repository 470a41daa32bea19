// The one backend factory: cpu, vulkan and auto, and the statistics every
// backend reports through the interface.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include "backends/vote_backend_factory.hpp"
#include "backends/vulkan/vulkan_vote_backend.hpp"
#include "recognition/fixture.hpp"
#include "vk_test_support.hpp"

using namespace sva;

TEST_CASE("backend factory: cpu is the reference and reports itself through the interface") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VoteSettings vs;
  vs.threads = 2;
  VoteBackendChoice c = make_vote_backend(BackendKind::cpu, *w.map, space, vs);
  REQUIRE(c.backend);
  CHECK(c.kind == BackendKind::cpu);
  CHECK(c.fallback_reason.empty());
  const BackendStats st = c.backend->statistics();
  CHECK(st.backend == "cpu");
  CHECK(st.device == "CPU reference (2 threads)");
  CHECK(st.last_kernel_ms == 0.0);
}

TEST_CASE("backend factory: auto takes a usable Vulkan device, else the CPU reference with the reason") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VulkanBackendOptions missing;
  missing.device = "no-such-gpu-name";
  CHECK_THROWS_AS(make_vote_backend(BackendKind::vulkan, *w.map, space, {}, missing), Error);
  VoteBackendChoice fallback = make_vote_backend(BackendKind::automatic, *w.map, space, {}, missing);
  CHECK(fallback.kind == BackendKind::cpu);
  CHECK(std::string(fallback.backend->name()) == "cpu");
  CHECK(fallback.fallback_reason.find("no-such-gpu-name") != std::string::npos);

  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});  // skips without a device
  const VulkanDeviceChoice device = probe_vulkan_device();
  VoteBackendChoice c = make_vote_backend(BackendKind::automatic, *w.map, space, {});
  if (device.type == "cpu" && !device.named) {
    // A software device (lavapipe) is slower than the CPU reference: auto skips it, saying why.
    CHECK(c.kind == BackendKind::cpu);
    CHECK(c.fallback_reason.find("software") != std::string::npos);
    CHECK(c.fallback_reason.find(device.name) != std::string::npos);
    // Named, it is used.
    VulkanBackendOptions named;
    named.device = device.name;
    c = make_vote_backend(BackendKind::automatic, *w.map, space, {}, named);
  }
  CHECK(c.kind == BackendKind::vulkan);
  CHECK(c.fallback_reason.empty());
  const BackendStats st = c.backend->statistics();
  CHECK(st.backend == "vulkan");
  CHECK(st.device == gpu->statistics().device);
  CHECK(st.map_chunks >= 1);
  CHECK(st.validation_messages == 0);
}

TEST_CASE("backend names parse to kinds, and anything else names the option") {
  CHECK(parse_backend_kind("cpu", "x") == BackendKind::cpu);
  CHECK(parse_backend_kind("vulkan", "x") == BackendKind::vulkan);
  CHECK(parse_backend_kind("auto", "x") == BackendKind::automatic);
  CHECK(std::string(backend_kind_name(BackendKind::automatic)) == "auto");
  try {
    parse_backend_kind("cuda", "sva eval: --backend");
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("sva eval: --backend") != std::string::npos);
    CHECK(std::string(e.what()).find("cuda") != std::string::npos);
  }
}
