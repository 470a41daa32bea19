// core/portable_math: the elementary functions that feed results. They must be
// as accurate as glibc's (within an ulp or two of them over the engine's
// ranges) and handle the special values; that they give the same bits on
// every CPU follows from using only exactly rounded operations, and the
// determinism suite checks it end to end under glibc's other variants.
#include <catch2/catch.hpp>

#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>

namespace {

// Distance in units in the last place between two finite doubles of one sign.
std::int64_t ulps(double a, double b) {
  if (a == b) return 0;
  std::int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  if (ia < 0) ia = std::numeric_limits<std::int64_t>::min() - ia;
  if (ib < 0) ib = std::numeric_limits<std::int64_t>::min() - ib;
  return ia > ib ? ia - ib : ib - ia;
}

// The largest ulp distance from glibc's function over n arguments uniform in [lo, hi).
std::int64_t worst(const std::function<double(double)>& ours, const std::function<double(double)>& theirs, double lo,
                   double hi, int n = 200000) {
  // Through a signed integer: a negative double cast to an unsigned one is undefined (x86-64 wraps it, aarch64
  // saturates it to 0, and the two drew other arguments).
  sva::util::Rng rng(7, static_cast<std::uint64_t>(static_cast<std::int64_t>(lo * 1000)),
                     static_cast<std::uint64_t>(static_cast<std::int64_t>(hi * 1000)));
  std::int64_t w = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.uniform(lo, hi);
    w = std::max(w, ulps(ours(x), theirs(x)));
  }
  return w;
}

}  // namespace

namespace pm = sva::pmath;

TEST_CASE("portable math: within 1 ulp of glibc over the engine's ranges") {
  // glibc's results are themselves within about 0.5 ulp of the true value, so 1
  // ulp apart means ours are within about 1.5.
  CHECK(worst(
            pm::exp, [](double x) { return std::exp(x); }, -30, 30) <= 1);
  CHECK(worst(
            pm::exp, [](double x) { return std::exp(x); }, -700, 700) <= 1);
  CHECK(worst(
            pm::exp2, [](double x) { return std::exp2(x); }, -60, 60) <= 1);
  CHECK(worst(
            pm::log, [](double x) { return std::log(x); }, 1e-300, 1e-290) <= 1);
  CHECK(worst(
            pm::log, [](double x) { return std::log(x); }, 0, 4) <= 1);
  CHECK(worst(
            pm::log, [](double x) { return std::log(x); }, 0, 1e6) <= 1);
  CHECK(worst(
            pm::log2, [](double x) { return std::log2(x); }, 1e-3, 1e3) <= 2);
  CHECK(worst(
            pm::sin, [](double x) { return std::sin(x); }, -10, 10) <= 1);
  CHECK(worst(
            pm::cos, [](double x) { return std::cos(x); }, -10, 10) <= 1);
  CHECK(worst(
            pm::sin, [](double x) { return std::sin(x); }, -1e5, 1e5) <= 1);
  CHECK(worst(
            pm::cos, [](double x) { return std::cos(x); }, -1e5, 1e5) <= 1);
  CHECK(worst(
            pm::atan, [](double x) { return std::atan(x); }, -50, 50) <= 1);
  CHECK(worst([](double x) { return pm::atan2(x, 0.3 - x); }, [](double x) { return std::atan2(x, 0.3 - x); }, -5, 5) <=
        1);
  CHECK(worst(
            pm::acos, [](double x) { return std::acos(x); }, -1, 1) <= 2);
  CHECK(worst([](double x) { return pm::hypot(x, 1.7 * x - 3); }, [](double x) { return std::hypot(x, 1.7 * x - 3); },
              -1e3, 1e3) <= 1);
}

TEST_CASE("portable math: exp2 scales its kernel by 2^k exactly, at every exponent down to the subnormals") {
  // exp2(x) is 2^f scaled by 2^k (k the nearest integer, |f| <= 1/2); the scaling is a product where the result is
  // normal and ldexp elsewhere. Both must give ldexp's bits: checked against ldexp of exp2(f), whose k is 0.
  sva::util::Rng rng(7);
  std::size_t checked = 0, subnormal = 0;
  for (int k = -1075; k <= 1023; ++k)
    for (double f : {-0.5, -0.49, -0.25, -1e-9, 0.0, 1e-9, 0.3, 0.4999, 0.5, rng.uniform(-0.5, 0.5)}) {
      const double x = k + f;
      if (x < -1075.0 || x >= 1024.0) continue;
      const double kk = std::nearbyint(x);
      const double want = std::ldexp(pm::exp2(x - kk), static_cast<int>(kk));
      INFO("x = " << x);
      CHECK(pm::exp2(x) == want);  // positive or +0: equal values are equal bits
      ++checked;
      subnormal += want > 0.0 && want < std::numeric_limits<double>::min();
    }
  CHECK(checked > 20000);
  CHECK(subnormal > 400);  // the ldexp path is exercised
  CHECK(pm::exp2(1023.5) < std::numeric_limits<double>::infinity());
  CHECK(pm::exp2(-1074.0) == std::numeric_limits<double>::denorm_min());
}

TEST_CASE("portable math: exact points, quadrants and special values") {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(pm::exp(0.0) == 1.0);
  CHECK(pm::exp(-inf) == 0.0);
  CHECK(pm::exp(inf) == inf);
  CHECK(pm::exp(1000.0) == inf);
  CHECK(std::isnan(pm::exp(nan)));
  CHECK(pm::exp2(10.0) == 1024.0);
  CHECK(pm::exp2(-3.0) == 0.125);
  CHECK(pm::log(1.0) == 0.0);
  CHECK(pm::log(0.0) == -inf);
  CHECK(std::isnan(pm::log(-1.0)));
  CHECK(pm::log(inf) == inf);
  CHECK(pm::log2(8.0) == 3.0);
  CHECK(pm::sin(0.0) == 0.0);
  CHECK(pm::cos(0.0) == 1.0);
  CHECK(std::isnan(pm::sin(inf)));
  double s, c;
  pm::sincos(std::numbers::pi, s, c);
  CHECK(c == -1.0);
  CHECK(std::fabs(s) < 1.3e-16);
  pm::sincos(-0.5 * std::numbers::pi, s, c);
  CHECK(s == -1.0);
  CHECK(std::fabs(c) < 1e-16);
  CHECK(std::isfinite(pm::sin(1e12)));  // past the exact reduction: deterministic, finite
  CHECK(pm::atan2(0.0, -1.0) == std::numbers::pi);
  CHECK(pm::atan2(-0.0, -1.0) == -std::numbers::pi);
  CHECK(pm::atan2(1.0, 0.0) == 0.5 * std::numbers::pi);
  CHECK(pm::atan2(-2.0, 0.0) == -0.5 * std::numbers::pi);
  CHECK(pm::atan2(1.0, 1.0) == std::atan2(1.0, 1.0));
  CHECK(pm::atan2(1e-300, -1.0) == std::atan2(1e-300, -1.0));
  CHECK(pm::atan2(1e300, 1e-300) == 0.5 * std::numbers::pi);
  CHECK(pm::atan2(inf, -inf) == std::atan2(inf, -inf));
  CHECK(pm::acos(1.0) == 0.0);
  CHECK(pm::acos(-1.0) == std::numbers::pi);
  CHECK(pm::acos(0.0) == std::acos(0.0));
  CHECK(std::isnan(pm::acos(1.0 + 1e-15)));
  CHECK(pm::hypot(3.0, 4.0) == 5.0);
  CHECK(pm::hypot(1e300, 1e300) == std::hypot(1e300, 1e300));
  CHECK(pm::hypot(0.0, 0.0) == 0.0);
}
