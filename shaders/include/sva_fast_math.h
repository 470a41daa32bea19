// Fast math of the shared vote math (sva_vote_math.h says why C++ and GLSL
// share one text): dot, cross, length and normalise written out so that no
// compiler reorders or fuses them, and this file's own exp, atan2 and sincos
// polynomials, since libm and GPU builtins differ in their last bits.
//
// Every operation here is exact by construction on any conformant device:
// Vulkan rounds + - * correctly (and `precise` forbids fusing them), floor,
// ceil, min, max, abs and comparisons are exact, and the two operations it
// does not round correctly - division (2.5 ULP) and square root (derived from
// inversesqrt) - go through sva_div and sva_sqrt, which compute the correctly
// rounded IEEE result with integer arithmetic in GLSL and are the CPU's own
// (IEEE) division and square root in C++. The contract holds for operands and
// results in the normal range; subnormals are flushed to zero by the GLSL
// versions (the vote math's values never come near 1e-38).
#ifndef SVA_FAST_MATH_H
#define SVA_FAST_MATH_H

#ifdef __cplusplus
#define SVA_PRECISE
#define SVA_FN inline
#else
#define SVA_PRECISE precise
#define SVA_FN
#endif

#define SVA_PI 3.14159265358979f
#define SVA_TWO_PI 6.28318530717959f
#define SVA_INV_TWO_PI 0.159154943091895f
#define SVA_HALF_PI 1.57079632679490f
#define SVA_QUARTER_PI 0.785398163397448f
#define SVA_LN2 0.693147180559945f
#define SVA_INV_LN2 1.44269504088896f

#ifdef __cplusplus
// x86-64 (SSE) divides and takes square roots correctly rounded, as IEEE 754 asks.
SVA_FN float sva_div(float a, float b) { return a / b; }
SVA_FN float sva_sqrt(float x) { return sqrt(x); }
#else
// bench/roofline/vote_math_device_division.comp defines SVA_ROOFLINE_DIVISION and brings the device's own division and
// square root instead, to weigh what the exact ones cost a device (`sva bench`); never the engine's kernels.
#ifndef SVA_ROOFLINE_DIVISION
#define SVA_F32_INF 0x7f800000u
#define SVA_F32_NAN 0x7fc00000u

// Test hook: added to the fast paths' first estimates below, so that a test
// kernel can check the corrections and the fallbacks on a device whose own
// division and square root happen to be exact (lavapipe).
#ifndef SVA_EXACT_ESTIMATE_SKEW
#define SVA_EXACT_ESTIMATE_SKEW 0
#endif

// The 25 quotient bits of ma / mb (ma in [mb, 2 mb), both below 2^25): q =
// floor(ma 2^24 / mb), and whether a remainder is left (the sticky bit). The
// device's own division estimates q to a few units (Vulkan allows 2.5 ULP);
// the remainder, exact in 64-bit integers, corrects it. An estimate that a
// few steps do not settle (a device far off its promise) takes the restoring
// division, bit by bit: the answer never depends on the estimate.
uint sva_div_significands(uint ma, uint mb, out bool sticky) {
  precise float qf = float(ma) / float(mb);  // sva-exact: an estimate, corrected exactly below
  int64_t q = int64_t(qf * 16777216.0f) + int64_t(SVA_EXACT_ESTIMATE_SKEW);
  int64_t r = (int64_t(ma) << 24) - q * int64_t(mb);
  for (int i = 0; i < 8; ++i) {
    if (r < 0l) {
      q -= 1l;
      r += int64_t(mb);
    } else if (r >= int64_t(mb)) {
      q += 1l;
      r -= int64_t(mb);
    } else {
      break;
    }
  }
  if (r >= 0l && r < int64_t(mb)) {
    sticky = r != 0l;
    return uint(q);
  }
  uint qs = 0u, rs = ma;  // restoring division: rs < 2 mb < 2^25
  for (int i = 0; i < 25; ++i) {
    qs <<= 1;
    if (rs >= mb) {
      rs -= mb;
      qs |= 1u;
    }
    rs <<= 1;
  }
  sticky = rs != 0u;
  return qs;
}

// a / b correctly rounded (to nearest, ties to even): the 25 quotient bits of
// the significands (24 and a round bit) and the sticky bit.
float sva_div(float a, float b) {
  uint ua = floatBitsToUint(a), ub = floatBitsToUint(b);
  uint sign = (ua ^ ub) & 0x80000000u;
  uint ea = (ua >> 23) & 0xffu, eb = (ub >> 23) & 0xffu;
  uint fa = ua & 0x7fffffu, fb = ub & 0x7fffffu;
  if ((ea == 255u && fa != 0u) || (eb == 255u && fb != 0u)) return uintBitsToFloat(SVA_F32_NAN);
  if (ea == 255u) return uintBitsToFloat(eb == 255u ? SVA_F32_NAN : sign | SVA_F32_INF);
  if (eb == 255u) return uintBitsToFloat(sign);
  if (eb == 0u) return uintBitsToFloat(ea == 0u ? SVA_F32_NAN : sign | SVA_F32_INF);  // b = 0 (subnormals flushed)
  if (ea == 0u) return uintBitsToFloat(sign);
  uint ma = fa | 0x800000u, mb = fb | 0x800000u;
  int e = int(ea) - int(eb) + 127;
  if (ma < mb) {  // quotient in [1, 2)
    ma <<= 1;
    e -= 1;
  }
  bool sticky;
  uint q = sva_div_significands(ma, mb, sticky);
  uint mant = q >> 1;
  if ((q & 1u) != 0u && (sticky || (mant & 1u) != 0u)) mant += 1u;
  if (mant == 0x1000000u) {
    mant >>= 1;
    e += 1;
  }
  if (e >= 255) return uintBitsToFloat(sign | SVA_F32_INF);
  if (e <= 0) return uintBitsToFloat(sign);
  return uintBitsToFloat(sign | (uint(e) << 23) | (mant & 0x7fffffu));
}

// The 25-bit integer square root of m 2^25 (m in [2^23, 2^25)): s =
// floor(sqrt(m 2^25)) and whether a remainder is left. As for the division:
// the device's square root estimates s, the exact remainder m 2^25 - s^2
// corrects it (s is right when 0 <= remainder <= 2 s), and an estimate a few
// steps do not settle takes the digit-by-digit root.
uint sva_sqrt_significand(uint64_t m, out bool sticky) {
  precise float sf = sqrt(float(m) * 33554432.0f);  // sva-exact: an estimate, corrected exactly below
  int64_t s = int64_t(sf) + int64_t(SVA_EXACT_ESTIMATE_SKEW);
  int64_t r = int64_t(m << 25) - s * s;
  for (int i = 0; i < 8; ++i) {
    if (r < 0l) {
      r += 2l * s - 1l;
      s -= 1l;
    } else if (r > 2l * s) {
      r -= 2l * s + 1l;
      s += 1l;
    } else {
      break;
    }
  }
  if (r >= 0l && r <= 2l * s) {
    sticky = r != 0l;
    return uint(s);
  }
  uint64_t rem = m << 25;  // in [2^48, 2^50): its root has 25 bits
  uint64_t res = 0ul, bit = 1ul << 48;
  for (int i = 0; i < 25; ++i) {
    if (rem >= res + bit) {
      rem -= res + bit;
      res = (res >> 1) + bit;
    } else {
      res >>= 1;
    }
    bit >>= 2;
  }
  sticky = rem != 0ul;
  return uint(res);
}

// sqrt(x) correctly rounded: 25 result bits of the significand's root (24 and
// a round bit) and the sticky bit. sqrt(-0) = -0; negatives give NaN.
float sva_sqrt(float x) {
  uint ux = floatBitsToUint(x);
  uint ex = (ux >> 23) & 0xffu, fx = ux & 0x7fffffu;
  if (ex == 255u && fx != 0u) return uintBitsToFloat(SVA_F32_NAN);
  if (ex == 0u) return uintBitsToFloat(ux & 0x80000000u);  // zero (subnormals flushed)
  if ((ux & 0x80000000u) != 0u) return uintBitsToFloat(SVA_F32_NAN);
  if (ex == 255u) return x;
  int e = int(ex) - 127;
  uint64_t m = uint64_t(fx | 0x800000u);
  if ((e & 1) != 0) {  // make the exponent even
    m <<= 1;
    e -= 1;
  }
  bool sticky;
  uint q = sva_sqrt_significand(m, sticky);
  uint mant = q >> 1;
  if ((q & 1u) != 0u && (sticky || (mant & 1u) != 0u)) mant += 1u;
  int be = (e >> 1) + 127;  // e is even
  if (mant == 0x1000000u) {
    mant >>= 1;
    be += 1;
  }
  return uintBitsToFloat((uint(be) << 23) | (mant & 0x7fffffu));
}
#endif  // SVA_ROOFLINE_DIVISION
#endif

SVA_FN float sva_dot(vec3 a, vec3 b) {
  SVA_PRECISE float d = a.x * b.x + a.y * b.y + a.z * b.z;
  return d;
}

SVA_FN vec3 sva_cross(vec3 a, vec3 b) {
  SVA_PRECISE vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return c;
}

SVA_FN float sva_length(vec3 a) { return sva_sqrt(sva_dot(a, a)); }

// The polynomials of exp and atan below, apart from their range reductions, so that the CPU's lane-parallel vote
// (host/src/backends/cpu/sample_votes.cpp) evaluates the same text without the branches around it.
// exp(r) for |r| <= ln2/2: Taylor to degree 8.
SVA_FN float sva_exp_series(float r) {
  SVA_PRECISE float e =
      1.0f + r * (1.0f + r * (0.5f + r * (1.0f / 6.0f + r * (1.0f / 24.0f + r * (1.0f / 120.0f + r * (1.0f / 720.0f + r * (1.0f / 5040.0f + r * (1.0f / 40320.0f))))))));
  return e;
}

// atan(u) for |u| <= 0.4143: the alternating Taylor series to u^15.
SVA_FN float sva_atan_series(float u) {
  SVA_PRECISE float u2 = u * u;
  SVA_PRECISE float s = u * (1.0f + u2 * (-1.0f / 3.0f + u2 * (1.0f / 5.0f + u2 * (-1.0f / 7.0f + u2 * (1.0f / 9.0f + u2 * (-1.0f / 11.0f + u2 * (1.0f / 13.0f + u2 * (-1.0f / 15.0f))))))));
  return s;
}

// The branching functions below are written as selects (every side computed, one kept): the same operations and
// roundings as branches, and the CPU evaluates them across SIMD lanes (host/src/backends/cpu/sample_votes.cpp).

// exp(x) for x <= 0 (Gaussian weights); x below -80 gives 0, x > 0 counts as 0.
// Range reduction x = k ln2 + r, |r| <= ln2/2, Taylor to degree 8 (error < 1e-8
// relative), then an exact scaling by 2^-k.
SVA_FN float sva_exp_neg(float x) {
  bool below = !(x > -80.0f);
  SVA_PRECISE float xc = x > 0.0f ? 0.0f : x;
  xc = below ? 0.0f : xc;
  SVA_PRECISE float kf = floor(xc * SVA_INV_LN2 + 0.5f);
  SVA_PRECISE float r = xc - kf * SVA_LN2;
  SVA_PRECISE float e = sva_exp_series(r);
  // e 2^-k: e lies in [0.7, 1.5] and k <= 116, so the product is a normal float
  // and exact, the same as k exact halvings, without their loop.
  int k = int(-kf);
  SVA_PRECISE float scale = uintBitsToFloat(uint(127 - k) << 23);
  SVA_PRECISE float v = e * scale;
  return below ? 0.0f : v;
}

// atan(t) for 0 <= t <= 1: above tan(pi/8) use atan(t) = pi/4 + atan((t-1)/(t+1)),
// so the alternating Taylor series runs on |u| <= 0.4143; terms to u^15 leave
// an error below 1e-7.
SVA_FN float sva_atan01(float t) {
  bool reduce = t > 0.41421356f;
  SVA_PRECISE float base = reduce ? SVA_QUARTER_PI : 0.0f;
  SVA_PRECISE float u = reduce ? sva_div(t - 1.0f, t + 1.0f) : t;
  return base + sva_atan_series(u);
}

// atan2(y, x) in [-pi, pi]; atan2(0, 0) = 0.
SVA_FN float sva_atan2(float y, float x) {
  SVA_PRECISE float ax = abs(x);
  SVA_PRECISE float ay = abs(y);
  SVA_PRECISE float hi = max(ax, ay);
  bool none = !(hi > 0.0f);
  SVA_PRECISE float lo = min(ax, ay);
  SVA_PRECISE float a = sva_atan01(sva_div(lo, none ? 1.0f : hi));
  a = ay > ax ? SVA_HALF_PI - a : a;
  a = x < 0.0f ? SVA_PI - a : a;
  a = y < 0.0f ? -a : a;
  return none ? 0.0f : a;
}

// vec2(sin x, cos x). |x| is reduced to [-pi, pi), halved (|h| <= pi/2, where
// the Taylor series to h^13 / h^14 err below 1e-9) and doubled back. Odd and
// even by construction (the sign of x is applied last): sincos(-x) is exactly
// (-sin x, cos x), which makes the two orders of a pair vote alike
// (sva_beta_offset).
SVA_FN vec2 sva_sincos(float x) {
  SVA_PRECISE float ax = abs(x);
  SVA_PRECISE float xr = ax - SVA_TWO_PI * floor((ax + SVA_PI) * SVA_INV_TWO_PI);
  SVA_PRECISE float h = 0.5f * xr;
  SVA_PRECISE float h2 = h * h;
  SVA_PRECISE float sh = h * (1.0f + h2 * (-1.0f / 6.0f + h2 * (1.0f / 120.0f + h2 * (-1.0f / 5040.0f + h2 * (1.0f / 362880.0f + h2 * (-1.0f / 39916800.0f + h2 * (1.0f / 6227020800.0f)))))));
  SVA_PRECISE float ch = 1.0f + h2 * (-0.5f + h2 * (1.0f / 24.0f + h2 * (-1.0f / 720.0f + h2 * (1.0f / 40320.0f + h2 * (-1.0f / 3628800.0f + h2 * (1.0f / 479001600.0f + h2 * (-1.0f / 87178291200.0f)))))));
  SVA_PRECISE float s = 2.0f * sh * ch;
  SVA_PRECISE float c = 1.0f - 2.0f * sh * sh;
  s = x < 0.0f ? -s : s;
  return vec2(s, c);
}

SVA_FN vec3 sva_normalize(vec3 v) {
  SVA_PRECISE float l = sva_length(v);
  bool none = !(l > 0.0f);
  SVA_PRECISE float d = none ? 1.0f : l;
  // One exact division and three products, not three divisions: on a GPU an exact division (above) costs several
  // products. The unit vector is within 1.5 units in the last place either way.
  SVA_PRECISE vec3 u = v * sva_div(1.0f, d);
  return none ? vec3(0.0f, 0.0f, 0.0f) : u;
}

#endif
