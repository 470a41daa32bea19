#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/fixed_point.hpp"
#include "spv/fixed_point_scatter.h"
#include "vk_test_support.hpp"
#include "util/rng.hpp"
#include "vulkan/context.hpp"

namespace {

struct Push {
  std::uint32_t count, bin_count, base;
};

}  // namespace

TEST_CASE("fixed-point scatter on the GPU equals the CPU sum bit for bit") {
  auto ctx = sva::test::vulkan_context_or_skip();
  INFO("device: " << ctx->info().name);
  const std::uint32_t n = 100000, bins = 97;
  sva::util::Rng rng(7);
  auto weights = ctx->create_buffer(n * sizeof(float));
  auto bin_ids = ctx->create_buffer(n * sizeof(std::uint32_t));
  auto sums = ctx->create_buffer(bins * sizeof(std::int64_t));
  std::vector<std::int64_t> expect(bins, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    float w = static_cast<float>(rng.uniform());
    if (i % 1000 == 0) w = NAN;    // never reaches a sum
    if (i % 1001 == 0) w = 3.0f;   // clamps to one unit
    if (i % 1002 == 0) w = -1.0f;  // clamps to zero
    std::uint32_t b = static_cast<std::uint32_t>(rng.below(bins + 3));  // some out of range: ignored
    weights.as<float>()[i] = w;
    bin_ids.as<std::uint32_t>()[i] = b;
    if (b < bins) expect[b] += sva::to_fixed(w);
  }
  auto pipeline = ctx->create_pipeline(sva_spv_fixed_point_scatter, 3, sizeof(Push));
  Push push{n, bins, 0};
  std::vector<std::uint8_t> pb(sizeof push);
  std::memcpy(pb.data(), &push, sizeof push);
  std::vector<double> kernel_ms;
  ctx->run({{&pipeline, {&weights, &bin_ids, &sums}, pb, (n + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE}}, &kernel_ms);
  if (ctx->info().timestamps) {
    REQUIRE(kernel_ms.size() == 1);
    CHECK(kernel_ms[0] >= 0.0);
  }
  std::vector<std::int64_t> got(sums.as<std::int64_t>(), sums.as<std::int64_t>() + bins);
  CHECK(got == expect);
  CHECK(ctx->validation_messages() == 0);
  for (const auto& m : ctx->validation_log()) WARN(m);
}

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
