#pragma once
// The error metrics of the paper's Sec 5 (DESIGN 7): translational error,
// angular error minimised over the object's symmetries (Eq 22), inertial
// distance, and the order statistics the curves report.
#include <sva/pose.hpp>

#include <optional>
#include <vector>

namespace sva::eval {

// Rotation angles and vectors: so3::angle_sincos and so3::log_sincos (<sva/base/so3.hpp>).

// Angle of the rotation that aligns the estimate with the truth, taking the
// object's symmetry into account (Eq 22): for an axis of revolution the
// minimum over all rotations about the axis (closed form), for a discrete
// group the minimum over its elements. Radians in [0, pi].
double angular_error(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry);

// The symmetry S (object frame) whose copy of the truth, R_true S, is nearest
// to the estimate in rotation: the minimiser of Eq 22 (identity when none).
glm::dmat3 closest_symmetry(const glm::dmat3& R_true, const glm::dmat3& R_est, const Symmetry& symmetry);

// |T_est - T'| with T' the translation of that nearest copy of the truth: the
// symmetry turns the object about the axis through `symmetry.point`, so the
// copy's translation is T + R (p - S p). For an axis through the origin this is
// |T_est - T|.
double translation_error(const RigidPose& truth, const RigidPose& estimate, const Symmetry& symmetry);

// The RMS displacement of a solid sphere of radius r carried by the error
// (DESIGN 7): sqrt(|dT|^2 + (4/5) r^2 (1 - cos theta)).
double inertial_distance(double translation_error_mm, double angle_rad, double radius_mm);

struct PoseError {
  double translation_mm = 0.0;
  double angular_rad = 0.0;
  double inertial_mm = 0.0;
};
PoseError pose_error(const RigidPose& truth, const RigidPose& estimate, const Symmetry& symmetry,
                     double inertial_radius_mm);

// Median (mean of the two middle values for an even count), the p-th
// percentile (0..100, linear interpolation between closest ranks) and the
// mean; nullopt for an empty set. The input is taken by value because it is sorted.
std::optional<double> median(std::vector<double> values);
std::optional<double> percentile(std::vector<double> values, double p);
std::optional<double> mean(const std::vector<double>& values);

}  // namespace sva::eval
