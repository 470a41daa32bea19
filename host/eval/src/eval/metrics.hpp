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

// The surface errors of the BOP benchmark (docs/pose-errors.md), over `points` sampled on the object's surface
// (object frame, mm). MSSD: the smallest, over the object's symmetries S (rotations about `centre`), of the
// largest distance between a point carried by the estimate and the same point carried by the truth's copy
// R_true S. Exact over the given rotations (each stops once it cannot beat the best so far).
double mssd(const RigidPose& truth, const RigidPose& estimate, const std::vector<glm::dvec3>& points,
            const std::vector<glm::dmat3>& symmetries, const glm::dvec3& centre);

class SurfaceDistance;
// ADD-S: the mean, over the points carried by the estimate, of their distance to the surface carried by the
// truth (BOP measures it to the nearest model vertex; the surface itself is the same without the vertices' gaps).
double adds(const RigidPose& truth, const RigidPose& estimate, const std::vector<glm::dvec3>& points,
            const SurfaceDistance& surface);

// Median (mean of the two middle values for an even count), the p-th
// percentile (0..100, linear interpolation between closest ranks) and the
// mean; nullopt for an empty set. The input is taken by value because it is sorted.
std::optional<double> median(std::vector<double> values);
std::optional<double> percentile(std::vector<double> values, double p);
std::optional<double> mean(const std::vector<double>& values);

}  // namespace sva::eval
