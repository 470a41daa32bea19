// A pair's fold terms, 8 bins side by side (fold_lanes.hpp says why). The 128-bit value and its top 32 bits are
// sva_log2_u128's prefix, per bin; the 32 squarings run over the 8 bins at once, branch-free: a squaring's top
// bit is the next bit of the logarithm and picks the shift (32 or 31) that brings the mantissa back into [1, 2).
#include "backends/cpu/fold_lanes.hpp"

#include <algorithm>

#include "backends/cpu/hot_path.hpp"
#include "belief/belief_math.hpp"

namespace sva::cpu {

namespace {

constexpr std::size_t kLanes = 8;

// sva_log2_u128's position of the top bit and its 32-bit mantissa.
inline void mantissa(belief_math::SvaU128 v, std::uint32_t* y, std::uint64_t* p) {
  const std::uint32_t top = v.hi != 0 ? 64u + belief_math::sva_msb64(v.hi) : belief_math::sva_msb64(v.lo);
  std::uint64_t m;
  if (top < 31u) {
    m = v.lo << (31u - top);
  } else {
    const std::uint32_t s = top - 31u;
    if (s == 0u)
      m = v.lo;
    else if (s >= 64u)
      m = v.hi >> (s - 64u);
    else
      m = (v.lo >> s) | (v.hi << (64u - s));
    m &= 0xffffffffu;
  }
  *y = static_cast<std::uint32_t>(m);  // below 2^32 in every branch
  *p = top;
}

}  // namespace

SVA_HOT_PATH void fold_units(const std::uint64_t* mass, std::size_t n, std::uint64_t total, std::uint64_t eps_units,
                             std::uint64_t floor_log, std::uint64_t* out) {
  const belief_math::SvaU128 base = belief_math::sva_mul_u64(total, eps_units);
  for (std::size_t i = 0; i < n; i += kLanes) {
    alignas(32) std::uint32_t y[kLanes];
    alignas(32) std::uint64_t p[kLanes], frac[kLanes] = {};
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::uint64_t m = mass[std::min(i + l, n - 1)];  // past n: the last bin again, never written
      mantissa(
          belief_math::sva_add_u128(base, belief_math::sva_u128(m >> (64 - SVA_EPS_FRAC_BITS), m << SVA_EPS_FRAC_BITS)),
          &y[l], &p[l]);
    }
    for (std::uint32_t bit = 0; bit < 32u; ++bit)
      for (std::size_t l = 0; l < kLanes; ++l) {
        const std::uint64_t sq = static_cast<std::uint64_t>(y[l]) * y[l];  // Q2.62, in [2^62, 2^64)
        const std::uint64_t one = sq >> 63;
        frac[l] |= one << (31u - bit);
        y[l] = static_cast<std::uint32_t>(sq >> (31u + one));
      }
    for (std::size_t l = 0; l < kLanes && i + l < n; ++l) out[i + l] = ((p[l] << 32) | frac[l]) - floor_log;
  }
}

}  // namespace sva::cpu
