// util::StandardFloats (sva/base/float_environment.hpp): sva computes with subnormal numbers kept and round to nearest,
// whatever its caller's thread holds, in its public calls and in every task of its worker pool, and gives the caller
// its own environment back.
#include <catch2/catch.hpp>

#include <sva/base/float_environment.hpp>
#include <sva/base/parallel.hpp>

#include <vector>

#include "base/flush_to_zero.hpp"

using sva::test::set_flush_to_zero;
using sva::util::standard_floats;
using sva::util::StandardFloats;

namespace {

// A product whose exact value is subnormal: 0 where results are flushed.
double subnormal_product() {
  volatile double tiny = 1e-300, scale = 1e-10;
  return tiny * scale;
}

}  // namespace

TEST_CASE("sva's floating-point environment keeps subnormal numbers, and the caller gets its own back") {
  REQUIRE(standard_floats());  // a test process starts in it
  CHECK(subnormal_product() > 0.0);
  if (!set_flush_to_zero(true)) return;  // no flush-to-zero to undo on this CPU
  CHECK_FALSE(standard_floats());
  CHECK(subnormal_product() == 0.0);  // the switch is real: the product is flushed
  {
    const StandardFloats floats;
    CHECK(standard_floats());
    CHECK(subnormal_product() > 0.0);
    const StandardFloats nested;  // already standard: nothing set, nothing restored
    CHECK(standard_floats());
  }
  CHECK_FALSE(standard_floats());  // the caller's flush-to-zero is back
  CHECK(subnormal_product() == 0.0);
  set_flush_to_zero(false);
  CHECK(standard_floats());
}

TEST_CASE("every task of a parallel loop computes in sva's environment, at any thread count and nesting") {
  const bool flushing = set_flush_to_zero(true);
  for (const unsigned threads : {1u, 2u, 4u}) {
    std::vector<int> standard(64, 0), product_kept(64, 0), inner(64 * 4, 0);
    sva::util::parallel_for(
        64,
        [&](std::size_t i) {
          standard[i] = standard_floats();
          product_kept[i] = subnormal_product() > 0.0;
          sva::util::parallel_for(
              4, [&](std::size_t j) { inner[4 * i + j] = standard_floats(); }, threads);
        },
        threads);
    INFO(threads << " threads");
    for (std::size_t i = 0; i < 64; ++i) {
      CHECK(standard[i] == 1);
      CHECK(product_kept[i] == 1);
    }
    for (int v : inner) CHECK(v == 1);
    if (flushing) CHECK_FALSE(standard_floats());  // the caller's own again after the loop
  }
  set_flush_to_zero(false);
}
