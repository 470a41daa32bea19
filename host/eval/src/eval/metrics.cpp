#include "eval/metrics.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "eval/surface_distance.hpp"

namespace sva::eval {

namespace {

double trace(const glm::dmat3& M) { return M[0][0] + M[1][1] + M[2][2]; }

}  // namespace

double angular_error(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry) {
  // The estimate is as good as the truth composed with any symmetry S of the
  // object (object frame): error = min_S angle((R_true S)^T R_est)
  // = min_S angle(Q S) with Q = R_est^T R_true.
  const glm::dmat3 Q = glm::transpose(R_est) * R_true;
  switch (symmetry.kind) {
    case Symmetry::Kind::none:
      return so3::angle_sincos(Q);
    case Symmetry::Kind::discrete: {
      double best = so3::angle_sincos(Q);  // the identity is always a symmetry
      for (const auto& S : symmetry.rotations) best = std::min(best, so3::angle_sincos(Q * S));
      return best;
    }
    case Symmetry::Kind::axis: {
      // With S = R_a(g) = cos g I + sin g [a]x + (1 - cos g) a a^T,
      // trace(Q S) = A cos g + B sin g + C, maximal at sqrt(A^2 + B^2) + C;
      // the smallest angle is the one with the largest trace.
      const glm::dvec3 a = glm::normalize(symmetry.axis);
      const double aQa = glm::dot(a, Q * a);
      const double A = trace(Q) - aQa;
      const double B = trace(Q * so3::hat(a));
      const double best_trace = std::sqrt(A * A + B * B) + aQa;
      return std::min(so3::angle_from_trace(best_trace), so3::angle_sincos(Q));
    }
  }
  assert(false);
  return so3::angle_sincos(Q);
}

glm::dmat3 closest_symmetry(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry) {
  const glm::dmat3 Q = glm::transpose(R_est) * R_true;
  switch (symmetry.kind) {
    case Symmetry::Kind::none:
      return glm::dmat3(1.0);
    case Symmetry::Kind::discrete: {
      glm::dmat3 best(1.0);
      double best_angle = so3::angle_sincos(Q);
      for (const auto& S : symmetry.rotations) {
        const double a = so3::angle_sincos(Q * S);
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
      const double B = trace(Q * so3::hat(a));
      return so3::about_axis(a, pmath::atan2(B, A));
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

double mssd(const RigidPose& truth, const RigidPose& estimate, const std::vector<glm::dvec3>& points,
            const std::vector<glm::dmat3>& symmetries, const glm::dvec3& centre) {
  double best = 1e300;
  for (const glm::dmat3& S : symmetries) {
    // The truth's copy: x -> R_true (S (x - c) + c) + T_true.
    const glm::dmat3 R = truth.R * S;
    const glm::dvec3 T = truth.R * (centre - S * centre) + truth.T;
    double worst = 0.0;  // squared
    for (const glm::dvec3& x : points) {
      const glm::dvec3 d = estimate.R * x + estimate.T - (R * x + T);
      worst = std::max(worst, glm::dot(d, d));
      if (worst >= best) break;  // this copy cannot be the nearest
    }
    best = std::min(best, worst);
  }
  return std::sqrt(best);
}

double adds(const RigidPose& truth, const RigidPose& estimate, const std::vector<glm::dvec3>& points,
            const SurfaceDistance& surface) {
  if (points.empty()) return 0.0;
  // In the truth's object frame, where the surface is: y = R_true^T (R_est x + T_est - T_true).
  const glm::dmat3 Rt = glm::transpose(truth.R);
  double sum = 0.0;
  for (const glm::dvec3& x : points) sum += surface.distance(Rt * (estimate.R * x + estimate.T - truth.T));
  return sum / static_cast<double>(points.size());
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
