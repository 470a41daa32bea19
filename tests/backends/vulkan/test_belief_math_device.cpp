// The belief's integer arithmetic (sva_belief_math.h: the fold's log2 of 128-bit
// products, the estimate's 2^-d weights) run on the device must equal the same
// header compiled as C++, bit for bit, over random and edge operands: the fold
// and estimate tests compare whole beliefs, where a fault in the votes hides one
// here.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

#include "backends/vulkan/gpu_layout.hpp"
#include "belief/belief_math.hpp"
#include "spv/belief_math_device.h"
#include "vk_test_support.hpp"

namespace {

namespace bm = sva::belief_math;

constexpr std::size_t kWords = 7;

// The fold's domain: 0 < mass <= total < 2^63, 0 < eps_units < 2^48; d any; mass_bits <= SVA_MAX_MASS_BITS.
std::vector<std::uint64_t> make_cases(std::size_t count) {
  sva::util::Rng rng(31, 7);
  const auto any = [&] { return (rng.below(std::uint64_t{1} << 32) << 32) | rng.below(std::uint64_t{1} << 32); };
  const auto below_bits = [&](unsigned bits) { return bits >= 64 ? any() : any() >> (64 - bits); };
  std::vector<std::uint64_t> in;
  for (std::size_t c = 0; c < count; ++c) {
    std::uint64_t total = below_bits(1 + static_cast<unsigned>(rng.below(63))) | 1;
    std::uint64_t mass = 1 + rng.below(total);
    std::uint64_t eps = below_bits(1 + static_cast<unsigned>(rng.below(48))) | 1;
    std::uint64_t d = below_bits(static_cast<unsigned>(rng.below(65)));
    std::uint64_t a = below_bits(static_cast<unsigned>(rng.below(65))), b = any();
    if (c % 16 == 1) mass = total;                   // all of the pair's mass in one bin
    if (c % 16 == 2) a = ~std::uint64_t{0}, b = a;   // the largest product
    if (c % 16 == 3) d = (std::uint64_t{40} << 32);  // exactly mass_bits below the maximum
    if (c % 16 == 4) total = (std::uint64_t{1} << 63) - 1, mass = total;
    in.insert(in.end(), {mass, total, eps, d, a, b, 1 + rng.below(SVA_MAX_MASS_BITS)});
  }
  return in;
}

std::vector<std::uint64_t> cpu_words(const std::uint64_t* in) {
  const std::uint64_t mass = in[0], total = in[1], eps = in[2], d = in[3], a = in[4], b = in[5];
  const auto mass_bits = static_cast<std::uint32_t>(in[6]);
  const bm::SvaU128 p = bm::sva_mul_u64(a, b);
  return {bm::sva_fold_units(mass, total, eps),
          bm::sva_floor_log(total, eps),
          bm::sva_exp2_neg_units(d, mass_bits),
          p.hi,
          p.lo,
          a != 0 ? bm::sva_msb64(a) : 0u,
          (a | b) != 0 ? bm::sva_log2_u128(bm::sva_u128(a, b)) : 0u};
}

}  // namespace

TEST_CASE("the belief's integer math on the device equals the CPU's bit for bit") {
  auto ctx = sva::test::vulkan_context_or_skip();
  const std::uint32_t n = 16384;
  const std::vector<std::uint64_t> in = make_cases(n);
  auto bin = ctx->create_buffer(in.size() * sizeof(std::uint64_t));
  auto bout = ctx->create_buffer(std::size_t{n} * kWords * sizeof(std::uint64_t));
  std::memcpy(bin.data(), in.data(), in.size() * sizeof(std::uint64_t));
  const sva::vk::Pipeline pipe =
      ctx->create_pipeline("belief_math_device", sva_spv_belief_math_device, 2, sizeof(std::uint32_t));
  ctx->run({sva::vk::Dispatch{&pipe, {&bin, &bout}, sva::gpu::push_bytes(n), (n + 63) / 64}});
  const auto* gpu = bout.as<std::uint64_t>();
  const char* names[kWords] = {"fold units", "floor log", "exp2_neg units", "mul hi", "mul lo", "msb", "log2"};
  std::size_t differing[kWords] = {};
  std::string example;
  for (std::uint32_t c = 0; c < n; ++c) {
    const std::vector<std::uint64_t> want = cpu_words(&in[std::size_t{c} * kWords]);
    for (std::size_t k = 0; k < kWords; ++k) {
      if (want[k] == gpu[std::size_t{c} * kWords + k]) continue;
      ++differing[k];
      if (example.empty()) {
        std::ostringstream os;
        os << "case " << c << " " << names[k] << ": cpu " << want[k] << " gpu " << gpu[std::size_t{c} * kWords + k];
        example = os.str();
      }
    }
  }
  std::ostringstream summary;
  summary << "belief math on " << ctx->info().name << ", " << n << " cases; differing:";
  std::size_t total = 0;
  for (std::size_t k = 0; k < kWords; ++k) {
    if (differing[k]) summary << " [" << names[k] << "] " << differing[k];
    total += differing[k];
  }
  if (total == 0) summary << " none";
  WARN(summary.str());
  INFO(example);
  CHECK(total == 0);
}
