// The belief's integer arithmetic (sva_belief_math.h) against long-double
// references: 128-bit products, log2, the fold term and the exp2 weights,
// with their monotonicity and their extremes.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <cmath>

#include "belief/belief_math.hpp"

using namespace sva;
namespace bm = sva::belief_math;

namespace {
__extension__ typedef unsigned __int128 u128;  // the exact reference (a GCC/Clang extension)
long double value_of(bm::SvaU128 v) {
  return std::ldexp(static_cast<long double>(v.hi), 64) + static_cast<long double>(v.lo);
}
double bits_of(std::uint64_t units) { return static_cast<double>(units) / bm::kUnitsPerBit; }
}  // namespace

TEST_CASE("128-bit product and sum are exact") {
  util::Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t a = rng.next() >> (rng.below(64)), b = rng.next() >> (rng.below(64));
    const u128 want = static_cast<u128>(a) * b;
    const bm::SvaU128 got = bm::sva_mul_u64(a, b);
    CHECK(got.hi == static_cast<std::uint64_t>(want >> 64));
    CHECK(got.lo == static_cast<std::uint64_t>(want));
    const bm::SvaU128 s = bm::sva_add_u128(got, bm::sva_u128(0, ~std::uint64_t{0}));
    const u128 ws = want + ~std::uint64_t{0};
    CHECK(s.hi == static_cast<std::uint64_t>(ws >> 64));
    CHECK(s.lo == static_cast<std::uint64_t>(ws));
  }
  CHECK(bm::sva_msb64(1) == 0);
  CHECK(bm::sva_msb64(~std::uint64_t{0}) == 63);
  CHECK(bm::sva_msb64(std::uint64_t{1} << 40 | 5) == 40);
}

TEST_CASE("integer log2 is within 2^-28 of the exact value over 128 bits, and monotone") {
  util::Rng rng(5);
  double worst = 0.0;
  std::uint64_t previous = 0;
  for (int e = 0; e < 128; ++e) {
    for (int i = 0; i < 40; ++i) {
      // Values with the top bit at e, increasing within each e.
      const std::uint64_t r = rng.next();
      bm::SvaU128 v = e >= 64 ? bm::sva_u128((std::uint64_t{1} << (e - 64)) | (e > 64 ? r >> (128 - e) : 0), rng.next())
                              : bm::sva_u128(0, (std::uint64_t{1} << e) | (e ? r >> (64 - e) : 0));
      const std::uint64_t got = bm::sva_log2_u128(v);
      worst = std::max(worst, std::abs(bits_of(got) - static_cast<double>(std::log2(value_of(v)))));
    }
    // Powers of two are exact and increase.
    const bm::SvaU128 p =
        e >= 64 ? bm::sva_u128(std::uint64_t{1} << (e - 64), 0) : bm::sva_u128(0, std::uint64_t{1} << e);
    const std::uint64_t lp = bm::sva_log2_u128(p);
    CHECK(lp == static_cast<std::uint64_t>(e) << 32);
    CHECK(lp >= previous);
    previous = lp;
  }
  CHECK(worst < std::ldexp(1.0, -28));
  // Monotone across neighbours where the mantissa truncates.
  for (std::uint64_t x = (std::uint64_t{1} << 40) - 3000; x < (std::uint64_t{1} << 40) + 3000; ++x)
    REQUIRE(bm::sva_log2_u128(bm::sva_u128(0, x)) <= bm::sva_log2_u128(bm::sva_u128(0, x + 1)));
}

TEST_CASE("the fold term is log2(1 + mass / (total eps)), never negative, growing with the mass") {
  const double eps = 1e-6;
  const std::uint64_t eu = bm::eps_units(eps);
  const double eps_q = std::ldexp(static_cast<double>(eu), -SVA_EPS_FRAC_BITS);
  util::Rng rng(9);
  double worst = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const std::uint64_t total = 1 + (rng.next() >> (8 + rng.below(54)));  // up to 2^56: the vote clamp's bound
    const std::uint64_t mass = 1 + rng.next() % total;
    const std::uint64_t got = bm::sva_fold_units(mass, total, eu);
    const double want = std::log2(1.0 + static_cast<double>(mass) / (static_cast<double>(total) * eps_q));
    worst = std::max(worst, std::abs(bits_of(got) - want));
    if (mass < total) REQUIRE(bm::sva_fold_units(mass + 1, total, eu) >= got);
  }
  CHECK(worst < 1e-7);
  // Extremes: one unit of mass against the largest total; all mass in one bin.
  const std::uint64_t big = std::uint64_t{1} << 62;
  CHECK(bm::sva_fold_units(1, big, eu) <= 2);
  CHECK(std::abs(bits_of(bm::sva_fold_units(big, big, eu)) - std::log2(1.0 + 1.0 / eps_q)) < 1e-7);
  CHECK(std::abs(bits_of(bm::sva_fold_units(7, 7, bm::eps_units(0.5))) - std::log2(3.0)) < 1e-8);
}

TEST_CASE("exp2 weights: floor(2^(mass_bits - d)) within 2e-8 relative, zero far below the maximum") {
  for (std::uint32_t bits : {0u, 7u, 20u, 39u, 40u}) {
    CHECK(bm::sva_exp2_neg_units(0, bits) == std::uint64_t{1} << bits);
    std::uint64_t previous = ~std::uint64_t{0};
    for (int i = 0; i <= 4000; ++i) {
      const std::uint64_t d = static_cast<std::uint64_t>(i) * 0x2345678ull;  // up to ~33 bits of evidence
      const std::uint64_t got = bm::sva_exp2_neg_units(d, bits);
      const double want = std::exp2(static_cast<double>(bits) - bits_of(d));
      REQUIRE(got <= previous);  // monotone in d
      previous = got;
      // floor() of the value, from a 31-bit mantissa: off by < 1 unit plus ~2^-26 relative.
      CHECK(std::abs(static_cast<double>(got) - want) <= 1.0 + want * 2e-8);
    }
    CHECK(bm::sva_exp2_neg_units((std::uint64_t{bits} + 1) << 32, bits) == 0);
  }
}

TEST_CASE("eps and mass-bit parameters") {
  CHECK(bm::eps_units(1e-6) == static_cast<std::uint64_t>(std::llround(std::ldexp(1e-6, 48))));
  CHECK_THROWS_WITH(bm::eps_units(0.0), Catch::Contains("eps"));
  CHECK_THROWS_WITH(bm::eps_units(1e-13), Catch::Contains("eps"));
  CHECK_THROWS_WITH(bm::eps_units(1.0), Catch::Contains("eps"));
  CHECK_THROWS_WITH(bm::eps_units(std::nan("")), Catch::Contains("eps"));
  // The pair bound keeps the largest possible offset below 2^63 units.
  for (double eps : {1e-12, 1e-6, 0.5}) {
    const std::uint64_t eu = bm::eps_units(eps);
    const std::uint64_t worst_term = bm::sva_fold_units(std::uint64_t{1} << 56, std::uint64_t{1} << 56, eu);
    CHECK(bm::max_pairs(eu) > 50'000'000);
    CHECK(static_cast<double>(bm::max_pairs(eu)) * static_cast<double>(worst_term) < std::ldexp(1.0, 63));
  }
  CHECK(bm::mass_bits(6751269) == 39);  // paper3d: 21^3 x 9^3 bins per object
  CHECK(bm::mass_bits(31752) == 40);    // letters: 21 x 21 x 72
  // Any bin count keeps bins x 2^mass_bits below 2^62.
  for (std::uint64_t bins :
       {std::uint64_t{1}, std::uint64_t{1} << 30, std::uint64_t{1} << 54, (std::uint64_t{1} << 60) - 1})
    CHECK(bins <= ((std::uint64_t{1} << 62) - 1) >> bm::mass_bits(bins));
}
