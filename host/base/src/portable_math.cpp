// fdlibm's elementary functions (Sun Microsystems, 1993: "Permission to use,
// copy, modify, and distribute this software is freely granted, provided that
// this notice is preserved"), as FreeBSD's msun and musl carry them, reduced
// to the double-precision paths sva needs. See portable_math.hpp for why.
#include <sva/base/portable_math.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

namespace sva::pmath {

namespace {

std::uint64_t bits(double x) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

double from_bits(std::uint64_t u) {
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

constexpr double kLn2Hi = 6.93147180369123816490e-01;  // 0x3fe62e42 fee00000
constexpr double kLn2Lo = 1.90821492927058770002e-10;  // 0x3dea39ef 35793c76
constexpr double kInvLn2 = 1.44269504088896338700e+00;
constexpr double kPiLo = 1.2246467991473531772e-16;  // pi - (double)pi

// exp(r) for |r| <= ln2/2, given r = hi - lo.
double exp_kernel(double hi, double lo) {
  constexpr double P1 = 1.66666666666666019037e-01, P2 = -2.77777777770155933842e-03, P3 = 6.61375632143793436117e-05,
                   P4 = -1.65339022054652515390e-06, P5 = 4.13813679705723846039e-08;
  const double r = hi - lo;
  const double rr = r * r;
  const double c = r - rr * (P1 + rr * (P2 + rr * (P3 + rr * (P4 + rr * P5))));
  return 1.0 + (r * c / (2.0 - c) - lo + hi);
}

// Reduces x (|x| < 2^19 pi/2) to y0 + y1 in [-pi/4, pi/4] and returns the
// quadrant (fdlibm's __rem_pio2, its medium case with both refinements).
int reduce_pio2(double x, double& y0, double& y1) {
  constexpr double kInvPio2 = 6.36619772367581382433e-01;
  constexpr double kPio2_1 = 1.57079632673412561417e+00, kPio2_1t = 6.07710050650619224932e-11;
  constexpr double kPio2_2 = 6.07710050630396597660e-11, kPio2_2t = 2.02226624879595063154e-21;
  const double n = std::nearbyint(x * kInvPio2);  // round to nearest, ties to even: exact and CPU-independent
  double r = x - n * kPio2_1;                     // exact: kPio2_1 has 33 significant bits and |n| < 2^20
  double w = n * kPio2_1t;
  const double t = r;  // second refinement, always: it keeps the result exact near multiples of pi/2
  w = n * kPio2_2;
  r = t - w;
  w = n * kPio2_2t - ((t - r) - w);
  y0 = r - w;
  y1 = (r - y0) - w;
  return static_cast<int>(static_cast<long long>(n) & 3);
}

double sin_kernel(double x, double y) {
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03, S3 = -1.98412698298579493134e-04,
                   S4 = 2.75573137070700676789e-06, S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  const double z = x * x;
  const double w = z * z;
  const double r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
  const double v = z * x;
  return x - ((z * (0.5 * y - v * r) - y) - v * S1);
}

double cos_kernel(double x, double y) {
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03, C3 = 2.48015872894767294178e-05,
                   C4 = -2.75573143513906633035e-07, C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  const double z = x * x;
  const double w = z * z;
  const double r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
  const double hz = 0.5 * z;
  const double v = 1.0 - hz;
  return v + (((1.0 - v) - hz) + (z * r - x * y));
}

// Arguments past the exact reduction's range are brought back by an exact fmod
// by the double nearest 2 pi: deterministic, though no longer within an ulp.
double wrap_large(double x) {
  constexpr double kLimit = 823549.6445;  // 2^19 * pi/2
  return std::fabs(x) < kLimit ? x : std::fmod(x, 2.0 * std::numbers::pi);
}

}  // namespace

double exp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.782712893383973096) return std::numeric_limits<double>::infinity();
  if (x < -745.13321910194110842) return 0.0;
  const double ax = std::fabs(x);
  if (ax < 0x1p-28) return 1.0 + x;
  if (ax <= 0.5 * std::numbers::ln2) return exp_kernel(x, 0.0);
  const double k = std::nearbyint(kInvLn2 * x);
  const double hi = x - k * kLn2Hi;  // exact: kLn2Hi has 32 significant bits and |k| < 2^11
  const double lo = k * kLn2Lo;
  return std::ldexp(exp_kernel(hi, lo), static_cast<int>(k));
}

double exp2(double x) {
  if (std::isnan(x)) return x;
  if (x >= 1024.0) return std::numeric_limits<double>::infinity();
  if (x < -1075.0) return 0.0;
  const double k = std::nearbyint(x);
  const double f = x - k;  // exact, |f| <= 1/2
  // f ln2 rounded once: a relative error of 2^-53 in an argument below 0.35 moves the result by under 0.2 ulp.
  const double y = exp_kernel(f * std::numbers::ln2, 0.0);  // in [2^-1/2, 2^1/2]
  const int e = static_cast<int>(k);
  // Scaling by a normal power of two is exact while y 2^e stays normal, as it does for these e: ldexp's bits without
  // its call (libm's scalbn was 3-4% of a light estimate's time).
  if (e >= -1021 && e <= 1023) return y * from_bits(static_cast<std::uint64_t>(e + 1023) << 52);
  return std::ldexp(y, e);
}

double log(double x) {
  if (std::isnan(x)) return x;
  if (x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return -std::numeric_limits<double>::infinity();
  if (std::isinf(x)) return x;
  constexpr double Lg1 = 6.666666666666735130e-01, Lg2 = 3.999999999940941908e-01, Lg3 = 2.857142874366239149e-01,
                   Lg4 = 2.222219843214978396e-01, Lg5 = 1.818357216161805012e-01, Lg6 = 1.531383769920937332e-01,
                   Lg7 = 1.479819860511658591e-01;
  int k = 0;
  if (x < std::numeric_limits<double>::min()) {  // subnormal: scale up
    k = -54;
    x *= 0x1p54;
  }
  // x = 2^k (1 + f) with 1 + f in [sqrt(2)/2, sqrt(2)].
  std::uint64_t u = bits(x);
  std::uint32_t hx = static_cast<std::uint32_t>(u >> 32);
  hx += 0x3ff00000 - 0x3fe6a09e;
  k += static_cast<int>(hx >> 20) - 0x3ff;
  hx = (hx & 0x000fffff) + 0x3fe6a09e;
  u = (static_cast<std::uint64_t>(hx) << 32) | (u & 0xffffffffu);
  const double f = from_bits(u) - 1.0;
  const double hfsq = 0.5 * f * f;
  const double s = f / (2.0 + f);
  const double z = s * s;
  const double w = z * z;
  const double t1 = w * (Lg2 + w * (Lg4 + w * Lg6));
  const double t2 = z * (Lg1 + w * (Lg3 + w * (Lg5 + w * Lg7)));
  const double r = t2 + t1;
  const double dk = k;
  return s * (hfsq + r) + dk * kLn2Lo - hfsq + f + dk * kLn2Hi;
}

double log2(double x) {
  if (!(x > 0.0) || std::isinf(x)) return log(x);
  // x = 2^e m with m in [sqrt(1/2), sqrt(2)): exact powers of two come out exact.
  int e;
  double m = std::frexp(x, &e);
  if (m < std::numbers::sqrt2 / 2) m *= 2.0, --e;
  return static_cast<double>(e) + log(m) * std::numbers::log2e;
}

void sincos(double x, double& s, double& c) {
  if (!std::isfinite(x)) {
    s = c = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  x = wrap_large(x);
  if (std::fabs(x) <= 0.25 * std::numbers::pi) {
    s = sin_kernel(x, 0.0);
    c = cos_kernel(x, 0.0);
    return;
  }
  double y0, y1;
  const int q = reduce_pio2(x, y0, y1);
  const double ks = sin_kernel(y0, y1), kc = cos_kernel(y0, y1);
  switch (q) {
    case 0:
      s = ks, c = kc;
      break;
    case 1:
      s = kc, c = -ks;
      break;
    case 2:
      s = -ks, c = -kc;
      break;
    default:
      s = -kc, c = ks;
      break;
  }
}

double sin(double x) {
  double s, c;
  sincos(x, s, c);
  return s;
}

double cos(double x) {
  double s, c;
  sincos(x, s, c);
  return c;
}

double atan(double x) {
  constexpr double atanhi[] = {4.63647609000806093515e-01, 7.85398163397448278999e-01, 9.82793723247329054082e-01,
                               1.57079632679489655800e+00};
  constexpr double atanlo[] = {2.26987774529616870924e-17, 3.06161699786838301793e-17, 1.39033110312309984516e-17,
                               6.12323399573676603587e-17};
  constexpr double aT[] = {3.33333333333329318027e-01,  -1.99999999998764832476e-01, 1.42857142725034663711e-01,
                           -1.11111104054623557880e-01, 9.09088713343650656196e-02,  -7.69187620504482999495e-02,
                           6.66107313738753120669e-02,  -5.83357013379057348645e-02, 4.97687799461593236017e-02,
                           -3.65315727442169155270e-02, 1.62858201153657823623e-02};
  if (std::isnan(x)) return x;
  const bool negative = std::signbit(x);
  double a = std::fabs(x);
  if (a >= 0x1p66) return negative ? -(atanhi[3] + atanlo[3]) : atanhi[3] + atanlo[3];
  int id = -1;
  if (a < 0.4375) {
    if (a < 0x1p-27) return x;
    a = x;  // keep the sign: the polynomial is odd
  } else if (a < 0.6875) {
    id = 0, a = (2.0 * a - 1.0) / (2.0 + a);
  } else if (a < 1.1875) {
    id = 1, a = (a - 1.0) / (a + 1.0);
  } else if (a < 2.4375) {
    id = 2, a = (a - 1.5) / (1.0 + 1.5 * a);
  } else {
    id = 3, a = -1.0 / a;
  }
  const double z = a * a;
  const double w = z * z;
  const double s1 = z * (aT[0] + w * (aT[2] + w * (aT[4] + w * (aT[6] + w * (aT[8] + w * aT[10])))));
  const double s2 = w * (aT[1] + w * (aT[3] + w * (aT[5] + w * (aT[7] + w * aT[9]))));
  if (id < 0) return a - a * (s1 + s2);
  const double r = atanhi[id] - ((a * (s1 + s2) - atanlo[id]) - a);
  return negative ? -r : r;
}

double atan2(double y, double x) {
  constexpr double pi = std::numbers::pi, pi_2 = 0.5 * std::numbers::pi;
  if (std::isnan(x) || std::isnan(y)) return x + y;
  if (x == 1.0) return atan(y);
  const bool ny = std::signbit(y), nx = std::signbit(x);
  if (y == 0.0) return nx ? (ny ? -pi : pi) : y;
  if (x == 0.0) return ny ? -pi_2 : pi_2;
  if (std::isinf(x)) {
    if (std::isinf(y)) return (ny ? -1.0 : 1.0) * (nx ? 0.75 * pi : 0.25 * pi);
    return nx ? (ny ? -pi : pi) : (ny ? -0.0 : 0.0);
  }
  if (std::isinf(y)) return ny ? -pi_2 : pi_2;
  const int ey = std::ilogb(y), ex = std::ilogb(x);
  double z;
  if (ey - ex > 60) {
    z = pi_2 + 0.5 * kPiLo;  // |y/x| > 2^60
  } else if (nx && ex - ey > 60) {
    z = 0.0;  // |y|/x < -2^-60
  } else {
    z = atan(std::fabs(y / x));
  }
  if (!nx) return ny ? -z : z;
  return ny ? (z - kPiLo) - pi : pi - (z - kPiLo);
}

double acos(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return std::numeric_limits<double>::quiet_NaN();
  // acos x = 2 atan(sqrt((1 - x) / (1 + x))): 1 - x and 1 + x are exact where
  // they matter (Sterbenz), so the result keeps its accuracy near x = +-1.
  return 2.0 * atan2(std::sqrt(1.0 - x), std::sqrt(1.0 + x));
}

double hypot(double x, double y) {
  x = std::fabs(x), y = std::fabs(y);
  if (std::isinf(x) || std::isinf(y)) return std::numeric_limits<double>::infinity();
  if (std::isnan(x) || std::isnan(y)) return x + y;
  const double big = x > y ? x : y, small = x > y ? y : x;
  if (big == 0.0) return 0.0;
  // Scaled by a power of two (exact), so that neither square over- nor underflows.
  const int e = std::ilogb(big);
  const double a = std::ldexp(big, -e), b = std::ldexp(small, -e);
  return std::ldexp(std::sqrt(a * a + b * b), e);
}

}  // namespace sva::pmath
