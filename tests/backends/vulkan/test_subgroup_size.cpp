#include <catch2/catch.hpp>

#include <cstdlib>
#include <string>

#include "vk_test_support.hpp"

// CI runs this suite at several lavapipe vector widths (LP_NATIVE_VECTOR_WIDTH, the ci-subgroup-* test presets), so
// that a kernel which assumes one subgroup size fails without a GPU. The presets name the size they expect in
// SVA_TEST_SUBGROUP_SIZE: this test proves the width reached the device, so the runs are not all the same run.
TEST_CASE("the device's subgroup size is the one the test run asks for (SVA_TEST_SUBGROUP_SIZE)") {
  auto ctx = sva::test::vulkan_context_or_skip();
  const std::uint32_t size = ctx->info().subgroup_size;
  WARN("device " << ctx->info().name << ": subgroup size " << size);
  CHECK(size >= 1);
  CHECK((size & (size - 1)) == 0);  // Vulkan: a power of two
  const char* want = std::getenv("SVA_TEST_SUBGROUP_SIZE");
  if (want != nullptr && *want != '\0') CHECK(std::to_string(size) == want);
}
