#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "core/fixed_point.hpp"
#include "vk_test_support.hpp"

TEST_CASE("to_fixed quantises, clamps and rejects NaN") {
  CHECK(sva::to_fixed(1.0f) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(2.0f) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(0.5f) == SVA_FIXED_ONE / 2);
  CHECK(sva::to_fixed(-0.1f) == 0);
  CHECK(sva::to_fixed(NAN) == 0);
  CHECK(sva::to_fixed(INFINITY) == SVA_FIXED_ONE);
  CHECK(sva::to_fixed(1e-9f) == 0);
}

TEST_CASE("an impossible device request is a clear error") {
  sva::vk::ContextOptions o;
  o.device = "no-such-gpu-name";
  try {
    sva::vk::Context ctx(o);
    FAIL("expected an error");
  } catch (const sva::Error& e) {
    std::string m = e.what();
    CHECK((m.find("no-such-gpu-name") != std::string::npos || m.find("no Vulkan device") != std::string::npos));
  }
}

TEST_CASE("buffers have device addresses and fills clear exactly their range") {
  auto ctx = sva::test::vulkan_context_or_skip();
  auto a = ctx->create_buffer(4096), b = ctx->create_buffer(64);
  CHECK(a.device_address() != 0);
  CHECK(b.device_address() != 0);
  CHECK(a.device_address() != b.device_address());
  std::memset(a.data(), 0x11, 4096);
  ctx->run({}, nullptr, {{&a, 0xffffffffu, 1024, 2048}, {&b, 7u}});
  const auto* w = a.as<std::uint32_t>();
  CHECK(w[255] == 0x11111111u);
  CHECK(w[256] == 0xffffffffu);
  CHECK(w[767] == 0xffffffffu);
  CHECK(w[768] == 0x11111111u);
  for (int i = 0; i < 16; ++i) CHECK(b.as<std::uint32_t>()[i] == 7u);
  CHECK_THROWS_AS(ctx->run({}, nullptr, {{&b, 0u, 2, 8}}), std::logic_error);  // misaligned
  CHECK(ctx->validation_messages() == 0);
}
