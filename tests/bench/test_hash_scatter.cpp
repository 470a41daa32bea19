#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include "backends/vulkan/vk_test_support.hpp"
#include "roofline/hash_scatter.hpp"

namespace {

void random_votes(std::size_t n, std::uint64_t distinct, std::vector<std::uint64_t>& keys,
                  std::vector<float>& weights) {
  sva::util::Rng rng(11, n, distinct);
  keys.resize(n);
  weights.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = (rng.below(distinct) * 0x9e3779b97f4a7c15ull) >> 2;  // structured 62-bit keys
    weights[i] = static_cast<float>(rng.uniform());
  }
}
}  // namespace

TEST_CASE("GPU hash scatter equals the CPU reference exactly, growing the table on overflow") {
  auto ctx = sva::test::vulkan_context_or_skip();
  std::vector<std::uint64_t> keys;
  std::vector<float> weights;
  random_votes(50000, 5000, keys, weights);
  sva::bench::HashScatter scatter(*ctx, 64);  // far too small: must grow, never drop a vote
  auto gpu = scatter.run(keys, weights);
  auto cpu = sva::bench::scatter_reference(keys, weights);
  CHECK(scatter.grow_count() >= 6);
  CHECK(gpu.size() == cpu.size());
  CHECK(gpu == cpu);
  CHECK(ctx->validation_messages() == 0);
}

TEST_CASE("GPU hash scatter gives the same sums when the input is split into tiny chunks") {
  auto ctx = sva::test::vulkan_context_or_skip();
  std::vector<std::uint64_t> keys;
  std::vector<float> weights;
  random_votes(3000, 400, keys, weights);
  sva::bench::HashScatter whole(*ctx, 1024);
  sva::bench::HashScatter chunked(*ctx, 1024);
  chunked.set_max_chunk(97);
  auto a = whole.run(keys, weights);
  auto b = chunked.run(keys, weights);
  CHECK(a == b);
  CHECK(a == sva::bench::scatter_reference(keys, weights));
  CHECK(ctx->validation_messages() == 0);
}
