#include <sva/base/so3.hpp>

#include <sva/base/portable_math.hpp>

#include <sva/base/finite.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sva::so3 {

namespace {
glm::dvec3 canonical_at_pi(glm::dvec3 r) {
  glm::dvec3 a = glm::abs(r);
  double lead = r.x;
  if (a.y > a.x && a.y >= a.z) lead = r.y;
  if (a.z > a.x && a.z > a.y) lead = r.z;
  return lead < 0.0 ? -r : r;
}
}  // namespace

glm::dmat3 hat(const glm::dvec3& v) {
  // glm is column-major: m[col][row].
  glm::dmat3 m(0.0);
  m[1][0] = -v.z;
  m[2][0] = v.y;
  m[0][1] = v.z;
  m[2][1] = -v.x;
  m[0][2] = -v.y;
  m[1][2] = v.x;
  return m;
}

glm::dvec3 vee(const glm::dmat3& M) {
  return 0.5 * glm::dvec3(M[1][2] - M[2][1], M[2][0] - M[0][2], M[0][1] - M[1][0]);
}

glm::dmat3 exp(const glm::dvec3& r) {
  const double theta = glm::length(r);
  const glm::dmat3 K = hat(r);
  double a, b;
  if (theta < 1e-6) {  // Taylor: sin(t)/t and (1-cos t)/t^2
    a = 1.0 - theta * theta / 6.0;
    b = 0.5 - theta * theta / 24.0;
  } else {
    a = pmath::sin(theta) / theta;
    b = (1.0 - pmath::cos(theta)) / (theta * theta);
  }
  return glm::dmat3(1.0) + a * K + b * (K * K);
}

glm::dvec3 log(const glm::dmat3& R) {
  // Through the quaternion: robust at every angle, including pi.
  const double tr = R[0][0] + R[1][1] + R[2][2];
  double w, x, y, z;
  if (tr > 0.0) {
    const double s = std::sqrt(tr + 1.0) * 2.0;
    w = 0.25 * s;
    x = (R[1][2] - R[2][1]) / s;
    y = (R[2][0] - R[0][2]) / s;
    z = (R[0][1] - R[1][0]) / s;
  } else if (R[0][0] > R[1][1] && R[0][0] > R[2][2]) {
    const double s = std::sqrt(1.0 + R[0][0] - R[1][1] - R[2][2]) * 2.0;
    w = (R[1][2] - R[2][1]) / s;
    x = 0.25 * s;
    y = (R[1][0] + R[0][1]) / s;
    z = (R[2][0] + R[0][2]) / s;
  } else if (R[1][1] > R[2][2]) {
    const double s = std::sqrt(1.0 + R[1][1] - R[0][0] - R[2][2]) * 2.0;
    w = (R[2][0] - R[0][2]) / s;
    x = (R[1][0] + R[0][1]) / s;
    y = 0.25 * s;
    z = (R[2][1] + R[1][2]) / s;
  } else {
    const double s = std::sqrt(1.0 + R[2][2] - R[0][0] - R[1][1]) * 2.0;
    w = (R[0][1] - R[1][0]) / s;
    x = (R[2][0] + R[0][2]) / s;
    y = (R[2][1] + R[1][2]) / s;
    z = 0.25 * s;
  }
  if (w < 0.0) {
    w = -w;
    x = -x;
    y = -y;
    z = -z;
  }
  glm::dvec3 v(x, y, z);
  const double s = glm::length(v);
  if (s < 1e-300) return glm::dvec3(0.0);
  const double theta = 2.0 * pmath::atan2(s, w);
  glm::dvec3 r = v * (theta / s);
  if (w < 1e-9) r = canonical_at_pi(r);
  return r;
}

double angle(const glm::dmat3& R) { return glm::length(log(R)); }

double angle_sincos(const glm::dmat3& R) {
  const double s = glm::length(vee(R));                        // sin(theta)
  const double c = (R[0][0] + R[1][1] + R[2][2] - 1.0) / 2.0;  // cos(theta)
  return pmath::atan2(s, c);
}

glm::dvec3 log_sincos(const glm::dmat3& R) {
  const double theta = angle_sincos(R);
  if (theta < 1e-12) return glm::dvec3(0.0);
  const glm::dvec3 s = vee(R);  // sin(theta) * axis
  if (pmath::sin(theta) > 1e-6) return theta / glm::length(s) * s;
  // Near pi the skew part vanishes: the axis is the dominant column of
  // (R + I) / 2 = u u^T (+ O(pi - theta)), its sign taken from the skew part.
  const glm::dmat3 B = 0.5 * (R + glm::dmat3(1.0));
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (B[i][i] > B[k][k]) k = i;
  glm::dvec3 u = glm::normalize(B[k]);
  if (glm::dot(u, s) < 0.0) u = -u;
  return theta * u;
}

double angle_from_trace(double trace) { return pmath::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0)); }

glm::dmat3 about_z(double a) { return exp(glm::dvec3(0.0, 0.0, a)); }

glm::dmat3 about_axis(const glm::dvec3& axis, double a) {
  return pmath::cos(a) * glm::dmat3(1.0) + pmath::sin(a) * hat(axis) +
         (1.0 - pmath::cos(a)) * glm::outerProduct(axis, axis);
}

glm::dmat3 orthonormalize(const glm::dmat3& M) {
  // Gram-Schmidt on the columns; enough for matrices that are rotations up to rounding.
  glm::dvec3 c0 = glm::normalize(M[0]);
  glm::dvec3 c1 = M[1] - glm::dot(M[1], c0) * c0;
  c1 = glm::normalize(c1);
  glm::dvec3 c2 = glm::cross(c0, c1);
  return glm::dmat3(c0, c1, c2);
}

bool is_rotation(const glm::dmat3& R) {
  if (!finite(R)) return false;
  const glm::dmat3 E = glm::transpose(R) * R - glm::dmat3(1.0);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!(std::abs(E[c][r]) < 1e-6)) return false;
  return glm::determinant(R) > 0.0;
}

glm::dvec3 rotate(const glm::dvec3& v, double angle, const glm::dvec3& k) {
  return v * pmath::cos(angle) + glm::cross(k, v) * pmath::sin(angle) + k * glm::dot(k, v) * (1.0 - pmath::cos(angle));
}

}  // namespace sva::so3
