#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/vulkan/vk_test_support.hpp"
#include "roofline/vote_math.hpp"

TEST_CASE("the vote math roofline runs the engine's exact math: the device's checksums are the CPU's") {
  auto ctx = sva::test::vulkan_context_or_skip();
  const sva::bench::VoteMathRoofline r = sva::bench::measure_vote_math(*ctx, 2048);
  CHECK(r.matches == 2048);
  // Most random matches align and cast a Gaussian of a few to 64 samples; a figure per sample needs them counted.
  CHECK(r.samples > 2048 * 4);
  CHECK(r.samples <= 2048 * 65);
  CHECK(r.exact_agrees);
  if (ctx->info().timestamps) {
    CHECK(r.exact_ms > 0.0);
    CHECK(r.device_division_ms > 0.0);
    CHECK(r.exact_samples_per_second() > 0.0);
  }
  CHECK(ctx->validation_messages() == 0);
}

TEST_CASE("the vote math roofline's checksum sees every sample: a moved contact changes it") {
  std::vector<float> m = sva::bench::vote_math_matches(64, 9);
  int changed = 0, compared = 0;
  for (std::size_t c = 0; c < 64; ++c) {
    float* f = &m[c * 28];
    std::uint32_t before[3], after[3];
    sva::bench::vote_math_checksum(f, before);
    if (before[2] == 0) continue;  // no sample inside the pose space
    ++compared;
    f[21] += 7.5f;  // the map pair's second contact, 1.5 translation bins away
    sva::bench::vote_math_checksum(f, after);
    if (std::memcmp(before, after, sizeof before) != 0) ++changed;
  }
  CHECK(compared > 16);
  CHECK(changed == compared);
}
