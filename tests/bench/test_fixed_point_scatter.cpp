// The bare fixed-point scatter of the roofline (bench/roofline): the engine's
// order-independent accumulation rule (DESIGN 4) on its own.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/vk_test_support.hpp"
#include "spv/fixed_point_scatter.h"
#include "votes/fixed_point.hpp"

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
    if (i % 1000 == 0) w = NAN;                                         // never reaches a sum
    if (i % 1001 == 0) w = 3.0f;                                        // clamps to one unit
    if (i % 1002 == 0) w = -1.0f;                                       // clamps to zero
    std::uint32_t b = static_cast<std::uint32_t>(rng.below(bins + 3));  // some out of range: ignored
    weights.as<float>()[i] = w;
    bin_ids.as<std::uint32_t>()[i] = b;
    if (b < bins) expect[b] += sva::to_fixed(w);
  }
  auto pipeline = ctx->create_pipeline("fixed_point_scatter", sva_spv_fixed_point_scatter, 3, sizeof(Push));
  Push push{n, bins, 0};
  std::vector<std::uint8_t> pb(sizeof push);
  std::memcpy(pb.data(), &push, sizeof push);
  std::vector<double> kernel_ms;
  ctx->run({{&pipeline, {&weights, &bin_ids, &sums}, pb, (n + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE}},
           &kernel_ms);
  if (ctx->info().timestamps) {
    REQUIRE(kernel_ms.size() == 1);
    CHECK(kernel_ms[0] >= 0.0);
  }
  std::vector<std::int64_t> got(sums.as<std::int64_t>(), sums.as<std::int64_t>() + bins);
  CHECK(got == expect);
  CHECK(ctx->validation_messages() == 0);
  for (const auto& m : ctx->validation_log()) WARN(m);
}
