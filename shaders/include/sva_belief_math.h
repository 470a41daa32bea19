// Integer arithmetic of the log-domain belief, written once for the C++
// reference (host/src/belief/belief_math.hpp) and the GLSL fold and
// reduction kernels.
//
// Why integers: the belief is a sum over pairs of log(1 + S_p(x) / eps), and
// on the GPU those terms arrive through atomics in any order. Floating-point
// sums depend on the order; 64-bit integer sums do not. So each term is a
// fixed-point number of bits of evidence (log2 units, SVA_BELIEF_FRAC_BITS
// fractional bits), computed here from the integer vote masses with integer
// operations only (+, -, *, shifts, comparisons), which every device and the
// CPU evaluate exactly alike. The same holds for the reductions' weights
// 2^(offset - max), used to sum the posterior mass of each object.
//
// Rules for includers: uint64_t and uint (32-bit) in scope; GLSL enables
// GL_EXT_shader_explicit_arithmetic_types_int64.
#ifndef SVA_BELIEF_MATH_H
#define SVA_BELIEF_MATH_H

#ifdef __cplusplus
#define SVA_BFN inline
#else
#define SVA_BFN
#endif

// Belief offsets: 2^32 units per bit of evidence. A pair adds at most
// log2(1 + 1/eps) <= 40 bits (eps >= 1e-12), so 2^23 pairs fit in 63 bits.
#define SVA_BELIEF_FRAC_BITS 32
// eps is quantised to a multiple of 2^-48 (SvaFoldParams::eps_units).
#define SVA_EPS_FRAC_BITS 48
// Object-mass weights carry at most this many fractional bits (see
// sva::belief_math::mass_bits: fewer when the pose space is huge).
#define SVA_MAX_MASS_BITS 40

// round(2^(-2^-k) * 2^31) for k = 1..32: the factors of 2^-f, one per bit of f.
#define SVA_EXP2_NEG_TABLE                                                                                   \
  0x5a82799au, 0x6ba27e65u, 0x75606374u, 0x7a92be8bu, 0x7d41d96eu, 0x7e9f0606u, 0x7f4f08aeu, 0x7fa765adu, \
      0x7fd3ab29u, 0x7fe9d3a9u, 0x7ff4e959u, 0x7ffa748eu, 0x7ffd3a3fu, 0x7ffe9d1eu, 0x7fff4e8eu, 0x7fffa747u, \
      0x7fffd3a4u, 0x7fffe9d2u, 0x7ffff4e9u, 0x7ffffa74u, 0x7ffffd3au, 0x7ffffe9du, 0x7fffff4fu, 0x7fffffa7u, \
      0x7fffffd4u, 0x7fffffeau, 0x7ffffff5u, 0x7ffffffau, 0x7ffffffdu, 0x7fffffffu, 0x7fffffffu, 0x80000000u

// An unsigned 128-bit integer.
struct SvaU128 {
  uint64_t hi;
  uint64_t lo;
};

SVA_BFN SvaU128 sva_u128(uint64_t hi, uint64_t lo) {
  SvaU128 r;
  r.hi = hi;
  r.lo = lo;
  return r;
}

SVA_BFN SvaU128 sva_add_u128(SvaU128 a, SvaU128 b) {
  uint64_t lo = a.lo + b.lo;
  return sva_u128(a.hi + b.hi + (lo < a.lo ? uint64_t(1) : uint64_t(0)), lo);
}

// The full product of two 64-bit integers, from four 32 x 32 -> 64 products.
SVA_BFN SvaU128 sva_mul_u64(uint64_t a, uint64_t b) {
  uint64_t m32 = uint64_t(0xffffffffu);
  uint64_t a0 = a & m32, a1 = a >> 32, b0 = b & m32, b1 = b >> 32;
  uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  uint64_t mid = (p00 >> 32) + (p01 & m32) + (p10 & m32);
  return sva_u128(p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32), (p00 & m32) | (mid << 32));
}

// Index of the highest set bit of x != 0 (a fixed-step search, no loop).
SVA_BFN uint sva_msb64(uint64_t x) {
  uint r = 0u;
  if ((x >> 32) != uint64_t(0)) { x >>= 32; r += 32u; }
  if ((x >> 16) != uint64_t(0)) { x >>= 16; r += 16u; }
  if ((x >> 8) != uint64_t(0)) { x >>= 8; r += 8u; }
  if ((x >> 4) != uint64_t(0)) { x >>= 4; r += 4u; }
  if ((x >> 2) != uint64_t(0)) { x >>= 2; r += 2u; }
  if ((x >> 1) != uint64_t(0)) { r += 1u; }
  return r;
}

// The mantissa: the 32 bits of v from its top bit p down, in [2^31, 2^32).
// The CPU's fold lanes (host/src/backends/cpu/fold_lanes.cpp) start from it too.
SVA_BFN uint64_t sva_log2_mantissa(SvaU128 v, uint p) {
  uint64_t y;
  if (p < 31u) {
    y = v.lo << (31u - p);
  } else {
    uint s = p - 31u;
    if (s == 0u) y = v.lo;
    else if (s >= 64u) y = v.hi >> (s - 64u);
    else y = (v.lo >> s) | (v.hi << (64u - s));
    y &= uint64_t(0xffffffffu);
  }
  return y;
}

// log2(v) for v != 0 in fixed point with 32 fractional bits. The top 32 bits
// of v form a mantissa y in [1, 2); each squaring of y yields one bit of
// log2(y) (y^2 >= 2: the bit is 1 and y halves). Truncation is monotone, so
// v <= w gives sva_log2_u128(v) <= sva_log2_u128(w).
SVA_BFN uint64_t sva_log2_u128(SvaU128 v) {
  uint p = v.hi != uint64_t(0) ? 64u + sva_msb64(v.hi) : sva_msb64(v.lo);
  uint64_t y = sva_log2_mantissa(v, p);
  uint64_t frac = uint64_t(0);
  for (uint i = 0u; i < 32u; ++i) {
    y = y * y;  // in [2^62, 2^64): Q2.62
    if ((y >> 63) != uint64_t(0)) {
      frac |= uint64_t(1) << (31u - i);
      y >>= 32;
    } else {
      y >>= 31;
    }
  }
  return (uint64_t(p) << 32) | frac;
}

// One pair's evidence for one bin, log2(1 + mass / (total * eps)), in belief
// units: log2(mass 2^48 + total eps_units) - log2(total eps_units). Needs
// 0 < mass <= total < 2^63 and 0 < eps_units < 2^48; the result is >= 0.
// The second term is the same for every bin of a pair: sva_floor_log computes
// it once, sva_fold_units_given takes it.
SVA_BFN uint64_t sva_floor_log(uint64_t total, uint64_t eps_units) {
  return sva_log2_u128(sva_mul_u64(total, eps_units));
}

SVA_BFN uint64_t sva_fold_units_given(uint64_t mass, uint64_t total, uint64_t eps_units, uint64_t floor_log) {
  SvaU128 with_votes =
      sva_add_u128(sva_mul_u64(total, eps_units), sva_u128(mass >> (64 - SVA_EPS_FRAC_BITS), mass << SVA_EPS_FRAC_BITS));
  return sva_log2_u128(with_votes) - floor_log;
}

SVA_BFN uint64_t sva_fold_units(uint64_t mass, uint64_t total, uint64_t eps_units) {
  return sva_fold_units_given(mass, total, eps_units, sva_floor_log(total, eps_units));
}

// floor(2^(mass_bits - d / 2^32)) for d >= 0 in belief units: the weight of a
// bin d units below the belief's maximum, in fixed point with mass_bits
// fractional bits (mass_bits <= SVA_MAX_MASS_BITS). The fraction of d is
// applied bit by bit from SVA_EXP2_NEG_TABLE, the integer part as a shift.
SVA_BFN uint64_t sva_exp2_neg_units(uint64_t d, uint mass_bits) {
#ifdef __cplusplus
  constexpr uint table[32] = {SVA_EXP2_NEG_TABLE};
#else
  const uint table[32] = uint[32](SVA_EXP2_NEG_TABLE);
#endif
  uint64_t whole = d >> SVA_BELIEF_FRAC_BITS;
  if (whole > uint64_t(mass_bits)) return uint64_t(0);
  uint frac = uint(d & uint64_t(0xffffffffu));
  uint64_t y = uint64_t(1u) << 31;  // 1.0 in Q1.31
  for (uint k = 0u; k < 32u; ++k)
    if ((frac & (0x80000000u >> k)) != 0u) y = (y * uint64_t(table[k])) >> 31;
  uint shift = 31u + uint(whole);  // y 2^(mass_bits - whole) / 2^31
  return shift >= mass_bits ? y >> (shift - mass_bits) : y << (mass_bits - shift);
}

#endif
