#include "eval/metrics.hpp"

#include <sva/base/portable_math.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sva::eval {

namespace {

// The vector v with sk(v) = (M - M^T) / 2; glm is column-major (M[col][row]).
glm::dvec3 unskew_antisymmetric(const glm::dmat3& M) {
  return 0.5 * glm::dvec3(M[1][2] - M[2][1], M[2][0] - M[0][2], M[0][1] - M[1][0]);
}

double trace(const glm::dmat3& M) { return M[0][0] + M[1][1] + M[2][2]; }

glm::dmat3 skew(const glm::dvec3& a) {
  // Columns of [a]x.
  return glm::dmat3(glm::dvec3(0.0, a.z, -a.y), glm::dvec3(-a.z, 0.0, a.x), glm::dvec3(a.y, -a.x, 0.0));
}

// The angle whose cosine is (trace - 1) / 2 when only the best trace is known
// (the axis case below), clamped against rounding.
double angle_from_trace(double tr) { return pmath::acos(std::clamp((tr - 1.0) / 2.0, -1.0, 1.0)); }

}  // namespace

double rotation_angle(const glm::dmat3& R) {
  const double s = glm::length(unskew_antisymmetric(R));  // sin(theta)
  const double c = (trace(R) - 1.0) / 2.0;                // cos(theta)
  return pmath::atan2(s, c);
}

glm::dvec3 rotation_vector(const glm::dmat3& R) {
  const double theta = rotation_angle(R);
  if (theta < 1e-12) return glm::dvec3(0.0);
  const glm::dvec3 s = unskew_antisymmetric(R);  // sin(theta) * axis
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

double angular_error(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry) {
  // The estimate is as good as the truth composed with any symmetry S of the
  // object (object frame): error = min_S angle((R_true S)^T R_est)
  // = min_S angle(Q S) with Q = R_est^T R_true.
  const glm::dmat3 Q = glm::transpose(R_est) * R_true;
  switch (symmetry.kind) {
    case Symmetry::Kind::none:
      return rotation_angle(Q);
    case Symmetry::Kind::discrete: {
      double best = rotation_angle(Q);  // the identity is always a symmetry
      for (const auto& S : symmetry.rotations) best = std::min(best, rotation_angle(Q * S));
      return best;
    }
    case Symmetry::Kind::axis: {
      // With S = R_a(g) = cos g I + sin g [a]x + (1 - cos g) a a^T,
      // trace(Q S) = A cos g + B sin g + C, maximal at sqrt(A^2 + B^2) + C;
      // the smallest angle is the one with the largest trace.
      const glm::dvec3 a = glm::normalize(symmetry.axis);
      const double aQa = glm::dot(a, Q * a);
      const double A = trace(Q) - aQa;
      const double B = trace(Q * skew(a));
      const double best_trace = std::sqrt(A * A + B * B) + aQa;
      return std::min(angle_from_trace(best_trace), rotation_angle(Q));
    }
  }
  assert(false);
  return rotation_angle(Q);
}

glm::dmat3 closest_symmetry(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry) {
  const glm::dmat3 Q = glm::transpose(R_est) * R_true;
  switch (symmetry.kind) {
    case Symmetry::Kind::none:
      return glm::dmat3(1.0);
    case Symmetry::Kind::discrete: {
      glm::dmat3 best(1.0);
      double best_angle = rotation_angle(Q);
      for (const auto& S : symmetry.rotations) {
        const double a = rotation_angle(Q * S);
        if (a < best_angle) {
          best_angle = a;
          best = S;
        }
      }
      return best;
    }
    case Symmetry::Kind::axis: {
      // trace(Q R_a(g)) = A cos g + B sin g + C (angular_error) is largest at g = atan2(B, A).
      const glm::dvec3 a = glm::normalize(symmetry.axis);
      const double A = trace(Q) - glm::dot(a, Q * a);
      const double B = trace(Q * skew(a));
      const double g = pmath::atan2(B, A);
      return pmath::cos(g) * glm::dmat3(1.0) + pmath::sin(g) * skew(a) +
             (1.0 - pmath::cos(g)) * glm::outerProduct(a, a);
    }
  }
  assert(false);
  return glm::dmat3(1.0);
}

double translation_error(const RigidPose& truth, const RigidPose& estimate, const Symmetry& symmetry) {
  if (symmetry.kind == Symmetry::Kind::none || symmetry.point == glm::dvec3(0.0))
    return glm::length(estimate.T - truth.T);
  const glm::dmat3 S = closest_symmetry(truth.R, estimate.R, symmetry);
  const glm::dvec3 copy = truth.T + truth.R * (symmetry.point - S * symmetry.point);
  return glm::length(estimate.T - copy);
}

double inertial_distance(double translation_error_mm, double angle_rad, double radius_mm) {
  const double rot = 0.8 * radius_mm * radius_mm * (1.0 - pmath::cos(angle_rad));
  return std::sqrt(translation_error_mm * translation_error_mm + std::max(0.0, rot));
}

PoseError pose_error(const RigidPose& truth, const RigidPose& estimate, const Symmetry& symmetry,
                     double inertial_radius_mm) {
  PoseError e;
  e.translation_mm = translation_error(truth, estimate, symmetry);
  e.angular_rad = angular_error(truth.R, estimate.R, symmetry);
  e.inertial_mm = inertial_distance(e.translation_mm, e.angular_rad, inertial_radius_mm);
  return e;
}

std::optional<double> median(std::vector<double> values) { return percentile(std::move(values), 50.0); }

std::optional<double> mean(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

std::optional<double> percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::nullopt;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double f = pos - static_cast<double>(lo);
  return values[lo] + f * (values[hi] - values[lo]);
}

}  // namespace sva::eval
