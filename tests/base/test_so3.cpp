// SO(3) in double (sva/base/so3.hpp): exp/log and the evaluation's log_sincos round trips near 0, in the middle
// and near pi, hat/vee, the closed-form axis rotation, and is_rotation as the input checks use it.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>

#include <cmath>
#include <limits>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include <sva/base/so3.hpp>

using namespace sva;

namespace {

constexpr double kPi = std::numbers::pi;

// An independent rotation: glm's axis-angle matrix.
glm::dmat3 rot(double angle, glm::dvec3 axis) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)));
}

glm::dvec3 random_axis(util::Rng& rng) { return glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal())); }

double max_abs_diff(const glm::dmat3& a, const glm::dmat3& b) {
  double m = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m = std::max(m, std::abs(a[c][r] - b[c][r]));
  return m;
}

}  // namespace

TEST_CASE("so3: exp/log round trip, composition, small angles") {
  util::Rng rng(21);
  for (int i = 0; i < 300; ++i) {
    const double th = i < 20 ? 1e-9 * i : rng.uniform(0.0, std::numbers::pi - 1e-6);
    const glm::dvec3 r = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal())) * th;
    const glm::dmat3 R = so3::exp(r);
    CHECK(glm::length(so3::log(R) - r) < 1e-9);
    CHECK(std::fabs(glm::determinant(R) - 1.0) < 1e-12);
    const glm::dmat3 I = glm::transpose(R) * R;
    CHECK(std::fabs(I[0][0] - 1) + std::fabs(I[0][1]) + std::fabs(I[1][2]) < 1e-12);
    // exp(r) exp(-r) = I; exp(a r) exp(b r) = exp((a + b) r).
    CHECK(so3::angle(so3::exp(r) * so3::exp(-r)) < 1e-9);
    CHECK(so3::angle(so3::exp(0.75 * r) * so3::exp(0.25 * r) * glm::transpose(R)) < 1e-9);
  }
}

TEST_CASE("so3: exp agrees with an independent axis-angle matrix, log inverts it near 0 and near pi") {
  util::Rng rng(5);
  for (double a : {0.0, 1e-12, 1e-7, 0.3, 1.0, 2.0, kPi - 1e-6, kPi - 1e-9}) {
    for (int i = 0; i < 20; ++i) {
      const glm::dvec3 axis = random_axis(rng);
      const glm::dmat3 R = so3::exp(axis * a);
      CHECK(max_abs_diff(R, rot(a, axis)) < 1e-12);
      CHECK(so3::is_rotation(R));
      const glm::dvec3 r = so3::log(R);
      CHECK(glm::length(r) == Approx(a).margin(1e-9));
      // The vector itself comes back, except within 2e-9 of pi, where log picks the canonical sign.
      if (a < kPi - 1e-8) CHECK(glm::length(r - axis * a) < 1e-7);
      CHECK(so3::angle(R) == Approx(a).margin(1e-9));
      // Within 2e-9 of pi the canonical sign turns the axis: the rotation by pi - d about -u is 2d from the one
      // about u.
      CHECK(max_abs_diff(so3::exp(r), R) < (a < kPi - 1e-8 ? 1e-12 : 1e-8));
    }
  }
}

TEST_CASE("so3: log at exactly pi is canonical: r and -r give one vector with a positive leading component") {
  util::Rng rng(9);
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 axis = random_axis(rng);
    const glm::dvec3 rp = so3::log(so3::exp(axis * kPi));
    const glm::dvec3 rm = so3::log(so3::exp(-axis * kPi));
    CHECK(glm::length(rp) == Approx(kPi).margin(1e-9));
    CHECK(glm::length(rp - rm) < 1e-6);
    CHECK(std::abs(glm::dot(glm::normalize(rp), axis)) == Approx(1.0).margin(1e-9));
    const glm::dvec3 m = glm::abs(rp);
    const double lead = m.x >= m.y && m.x >= m.z ? rp.x : (m.y >= m.z ? rp.y : rp.z);
    CHECK(lead > 0.0);
    CHECK(max_abs_diff(so3::exp(rp), so3::exp(axis * kPi)) < 1e-9);
  }
}

TEST_CASE("so3: angle_sincos is exact near 0, in the middle and near pi") {
  for (double a : {0.0, 1e-7, 0.3, 1.0, 2.0, kPi - 1e-7, kPi})
    for (glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0.3, -0.5, 0.8), glm::dvec3(0, 0, -1)}) {
      CHECK(so3::angle_sincos(rot(a, axis)) == Approx(a).margin(1e-9));
      CHECK(so3::angle(rot(a, axis)) == Approx(a).margin(1e-9));
    }
}

TEST_CASE("so3: log_sincos inverts axis-angle, also near 0 and pi") {
  util::Rng rng(21, 4);
  for (int i = 0; i < 200; ++i) {
    const glm::dmat3 R = so3::exp(random_axis(rng) * rng.uniform(0.0, kPi));
    const glm::dvec3 v = so3::log_sincos(R);
    REQUIRE(glm::length(v) <= kPi + 1e-12);
    const glm::dmat3 back = glm::length(v) > 0 ? rot(glm::length(v), v) : glm::dmat3(1.0);
    CHECK(so3::angle_sincos(glm::transpose(back) * R) < 1e-9);
  }
  for (double a : {0.0, 1e-9, kPi - 1e-9, kPi}) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.2, -0.7, 0.4));
    const glm::dvec3 v = so3::log_sincos(rot(a, axis));
    CHECK(glm::length(v) == Approx(a).margin(1e-9));
    if (a > 1.0) CHECK(std::abs(glm::dot(glm::normalize(v), axis)) == Approx(1.0).margin(1e-6));
  }
}

TEST_CASE("so3: hat is the cross product, vee inverts it, about_axis and about_z are rotations about their axes") {
  const glm::dvec3 v(0.3, -1.7, 2.5), x(-4.0, 0.5, 1.25);
  CHECK(glm::length(so3::hat(v) * x - glm::cross(v, x)) < 1e-15);
  CHECK(so3::vee(so3::hat(v)) == v);
  CHECK(max_abs_diff(so3::hat(v), -glm::transpose(so3::hat(v))) == 0.0);
  // vee of a rotation is sin(angle) * axis.
  const glm::dvec3 axis = glm::normalize(glm::dvec3(1.0, 2.0, -2.0));
  CHECK(glm::length(so3::vee(rot(0.8, axis)) - std::sin(0.8) * axis) < 1e-12);
  for (double a : {-2.0, 0.0, 0.4, 3.0}) {
    CHECK(max_abs_diff(so3::about_axis(axis, a), rot(a, axis)) < 1e-12);
    CHECK(max_abs_diff(so3::about_z(a), rot(a, {0, 0, 1})) < 1e-12);
  }
  CHECK(so3::angle_from_trace(3.0) == 0.0);
  CHECK(so3::angle_from_trace(-1.0) == Approx(kPi).margin(1e-12));
  CHECK(so3::angle_from_trace(3.0 + 1e-12) == 0.0);  // clamped, not NaN
}

TEST_CASE("so3: is_rotation accepts rotations and rejects NaN, infinities, reflections and non-orthonormal matrices") {
  util::Rng rng(3);
  CHECK(so3::is_rotation(glm::dmat3(1.0)));
  for (int i = 0; i < 50; ++i) CHECK(so3::is_rotation(so3::exp(random_axis(rng) * rng.uniform(0.0, kPi))));
  CHECK(so3::is_rotation(so3::exp(glm::dvec3(kPi, 0.0, 0.0))));

  const glm::dmat3 R = so3::exp(glm::dvec3(0.3, -0.2, 0.5));
  glm::dmat3 bad = R;
  bad[1][2] = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(so3::is_rotation(bad));
  bad = R;
  bad[0][0] = std::numeric_limits<double>::infinity();
  CHECK_FALSE(so3::is_rotation(bad));
  // Reflections: orthonormal, determinant -1.
  CHECK_FALSE(so3::is_rotation(-R));
  CHECK_FALSE(so3::is_rotation(glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1))));
  // Not orthonormal: scaled, sheared, singular; and the tolerance is 1e-6 per entry of R^T R - I.
  CHECK_FALSE(so3::is_rotation(1.001 * R));
  glm::dmat3 sheared = R;
  sheared[1] += 0.01 * sheared[0];
  CHECK_FALSE(so3::is_rotation(sheared));
  CHECK_FALSE(so3::is_rotation(glm::dmat3(0.0)));
  CHECK(so3::is_rotation((1.0 + 1e-8) * R));        // |R^T R - I| about 2e-8: a rotation up to rounding
  CHECK_FALSE(so3::is_rotation((1.0 + 1e-6) * R));  // about 2e-6: not
  // orthonormalize repairs a rotation up to rounding.
  CHECK(so3::is_rotation(so3::orthonormalize((1.0 + 1e-4) * R + 1e-5 * glm::dmat3(1.0))));
  CHECK(max_abs_diff(so3::orthonormalize(R), R) < 1e-14);
}
