// Fast math of the shared vote math (sva_vote_math.h says why C++ and GLSL
// share one text): dot, cross, length and normalise written out so that no
// compiler reorders or fuses them, and this file's own exp, atan2 and sincos
// polynomials, since libm and GPU builtins differ in their last bits. Only
// + - * / sqrt floor ceil and comparisons on 32-bit floats.
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
#define SVA_HALF_PI 1.57079632679490f
#define SVA_QUARTER_PI 0.785398163397448f
#define SVA_LN2 0.693147180559945f

SVA_FN float sva_dot(vec3 a, vec3 b) {
  SVA_PRECISE float d = a.x * b.x + a.y * b.y + a.z * b.z;
  return d;
}

SVA_FN vec3 sva_cross(vec3 a, vec3 b) {
  SVA_PRECISE vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return c;
}

SVA_FN float sva_length(vec3 a) { return sqrt(sva_dot(a, a)); }

// exp(x) for x <= 0 (Gaussian weights); x below -80 gives 0. Range reduction
// x = k ln2 + r, |r| <= ln2/2, Taylor to degree 8 (error < 1e-8 relative),
// then k exact halvings.
SVA_FN float sva_exp_neg(float x) {
  if (!(x > -80.0f)) return 0.0f;
  if (x > 0.0f) x = 0.0f;
  SVA_PRECISE float kf = floor(x / SVA_LN2 + 0.5f);
  SVA_PRECISE float r = x - kf * SVA_LN2;
  SVA_PRECISE float e =
      1.0f + r * (1.0f + r * (0.5f + r * (1.0f / 6.0f + r * (1.0f / 24.0f + r * (1.0f / 120.0f + r * (1.0f / 720.0f + r * (1.0f / 5040.0f + r * (1.0f / 40320.0f))))))));
  int k = int(-kf);
  for (int i = 0; i < 128; ++i) {
    if (i >= k) break;
    e = e * 0.5f;
  }
  return e;
}

// atan(t) for 0 <= t <= 1: above tan(pi/8) use atan(t) = pi/4 + atan((t-1)/(t+1)),
// so the alternating Taylor series runs on |u| <= 0.4143; terms to u^15 leave
// an error below 1e-7.
SVA_FN float sva_atan01(float t) {
  SVA_PRECISE float base = 0.0f;
  SVA_PRECISE float u = t;
  if (t > 0.41421356f) {
    base = SVA_QUARTER_PI;
    u = (t - 1.0f) / (t + 1.0f);
  }
  SVA_PRECISE float u2 = u * u;
  SVA_PRECISE float s = u * (1.0f + u2 * (-1.0f / 3.0f + u2 * (1.0f / 5.0f + u2 * (-1.0f / 7.0f + u2 * (1.0f / 9.0f + u2 * (-1.0f / 11.0f + u2 * (1.0f / 13.0f + u2 * (-1.0f / 15.0f))))))));
  return base + s;
}

// atan2(y, x) in [-pi, pi]; atan2(0, 0) = 0.
SVA_FN float sva_atan2(float y, float x) {
  SVA_PRECISE float ax = abs(x);
  SVA_PRECISE float ay = abs(y);
  SVA_PRECISE float hi = max(ax, ay);
  if (!(hi > 0.0f)) return 0.0f;
  SVA_PRECISE float lo = min(ax, ay);
  SVA_PRECISE float a = sva_atan01(lo / hi);
  if (ay > ax) a = SVA_HALF_PI - a;
  if (x < 0.0f) a = SVA_PI - a;
  if (y < 0.0f) a = -a;
  return a;
}

// vec2(sin x, cos x). |x| is reduced to [-pi, pi), halved (|h| <= pi/2, where
// the Taylor series to h^13 / h^14 err below 1e-9) and doubled back. Odd and
// even by construction (the sign of x is applied last): sincos(-x) is exactly
// (-sin x, cos x), which makes the two orders of a pair vote alike
// (sva_beta_offset).
SVA_FN vec2 sva_sincos(float x) {
  SVA_PRECISE float ax = abs(x);
  SVA_PRECISE float xr = ax - SVA_TWO_PI * floor((ax + SVA_PI) / SVA_TWO_PI);
  SVA_PRECISE float h = 0.5f * xr;
  SVA_PRECISE float h2 = h * h;
  SVA_PRECISE float sh = h * (1.0f + h2 * (-1.0f / 6.0f + h2 * (1.0f / 120.0f + h2 * (-1.0f / 5040.0f + h2 * (1.0f / 362880.0f + h2 * (-1.0f / 39916800.0f + h2 * (1.0f / 6227020800.0f)))))));
  SVA_PRECISE float ch = 1.0f + h2 * (-0.5f + h2 * (1.0f / 24.0f + h2 * (-1.0f / 720.0f + h2 * (1.0f / 40320.0f + h2 * (-1.0f / 3628800.0f + h2 * (1.0f / 479001600.0f + h2 * (-1.0f / 87178291200.0f)))))));
  SVA_PRECISE float s = 2.0f * sh * ch;
  SVA_PRECISE float c = 1.0f - 2.0f * sh * sh;
  if (x < 0.0f) s = -s;
  return vec2(s, c);
}

SVA_FN vec3 sva_normalize(vec3 v) {
  SVA_PRECISE float l = sva_length(v);
  if (!(l > 0.0f)) return vec3(0.0f, 0.0f, 0.0f);
  return v / l;
}

#endif
