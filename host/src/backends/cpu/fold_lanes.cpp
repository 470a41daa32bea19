// A pair's fold terms, 32 bins side by side (fold_lanes.hpp says why). The 128-bit value and its top 32 bits are
// sva_log2_u128's prefix, per bin; the 32 squarings run over the 32 bins at once, branch-free: a squaring's top
// bit is the next bit of the logarithm and picks the shift (32 or 31) that brings the mantissa back into [1, 2).
#include "backends/cpu/fold_lanes.hpp"

#include <bit>

#include "backends/cpu/hot_path.hpp"
#include "belief/belief_math.hpp"

namespace sva::cpu {

namespace {

// Bins per group. GCC vectorizes the squarings' lane loop only when it is long enough to pay (8 lanes stayed
// scalar); 32 lanes are four AVX-512 or eight AVX2 registers of independent chains, which hide the multiply's latency.
constexpr std::size_t kLanes = 32;

// sva_log2_u128's position of the top bit (v != 0: std::countl_zero is sva_msb64 in one instruction) and its
// mantissa (the shared text's own).
inline void mantissa(belief_math::SvaU128 v, std::uint64_t* y, std::uint64_t* p) {
  const std::uint32_t top = v.hi != 0 ? 127u - static_cast<std::uint32_t>(std::countl_zero(v.hi))
                                      : 63u - static_cast<std::uint32_t>(std::countl_zero(v.lo));
  *y = belief_math::sva_log2_mantissa(v, top);
  *p = top;
}

}  // namespace

SVA_HOT_PATH void fold_units(const std::uint64_t* mass, std::size_t n, std::uint64_t total, std::uint64_t eps_units,
                             std::uint64_t floor_log, std::uint64_t* out) {
  const belief_math::SvaU128 base = belief_math::sva_mul_u64(total, eps_units);
  const std::size_t whole = n - n % kLanes;
  for (std::size_t i = 0; i < whole; i += kLanes) {
    // 64-bit lanes throughout: the mantissa is below 2^32, so its square is exact, and one lane width lets the
    // loop below vectorize (mixed 32/64-bit lanes kept it scalar).
    alignas(64) std::uint64_t y[kLanes], p[kLanes], frac[kLanes];
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::uint64_t m = mass[i + l];
      mantissa(
          belief_math::sva_add_u128(base, belief_math::sva_u128(m >> (64 - SVA_EPS_FRAC_BITS), m << SVA_EPS_FRAC_BITS)),
          &y[l], &p[l]);
      frac[l] = 0;
    }
    for (std::uint32_t bit = 0; bit < 32u; ++bit)
      for (std::size_t l = 0; l < kLanes; ++l) {
        const std::uint64_t sq = y[l] * y[l];  // Q2.62, in [2^62, 2^64)
        const std::uint64_t one = sq >> 63;    // the next bit, most significant first
        frac[l] = (frac[l] << 1) | one;
        y[l] = (sq >> 31) >> one;  // back into [2^31, 2^32)
      }
    for (std::size_t l = 0; l < kLanes; ++l) out[i + l] = ((p[l] << 32) | frac[l]) - floor_log;
  }
  // The last bins, fewer than a group, by the shared text itself.
  for (std::size_t i = whole; i < n; ++i)
    out[i] = belief_math::sva_fold_units_given(mass[i], total, eps_units, floor_log);
}

}  // namespace sva::cpu
