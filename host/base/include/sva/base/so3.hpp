#pragma once
// SO(3), the rotation group, in double precision on the host: the one home of the
// host's rotation math (bin centres, the refined estimate, scene symmetries, the
// evaluation's error metrics, input checks, tests), in the manner of Sophus (one
// header per Lie group). The float versions that decide bins live in the shared GLSL
// headers (sva_quaternion.h, sva_vote_math.h).
//
// Conventions:
//  - A rotation is a glm::dmat3 acting on column vectors (x' = R x); glm is
//    column-major, so M[col][row].
//  - The tangent vector (Lie algebra so(3)) is the Rodrigues vector r = axis * angle
//    (radians); exp and log map between the two. log returns |r| <= pi and at
//    |r| = pi, where r and -r are the same rotation, the largest-magnitude
//    component is positive (the same rule as sva_quat_to_rodrigues). The rule
//    applies where the quaternion's w < 1e-9, i.e. within about 2e-9 of pi.
//  - hat(v) is the skew matrix with hat(v) x = v x x (cross product); vee is its
//    inverse, applied to the antisymmetric part of any matrix.
//  - Every transcendental function that feeds a result is sva::pmath's (the same bits
//    on every CPU); the formulas are fixed operation for operation: results are
//    compared bit for bit (golden digests).
//
// Two logarithms and two angles: log/angle (through the quaternion, canonical at
// pi) serve recognition; log_sincos/angle_sincos (atan2 of the skew and symmetric
// parts, as the evaluation has always measured) serve the error metrics. Both are
// accurate at every angle, but they differ in the last bits, and each one's callers'
// outputs are pinned, so both stay.
#include <glm/glm.hpp>

namespace sva::so3 {

// hat: vector -> skew matrix [v]x, with hat(v) * x = cross(v, x).
glm::dmat3 hat(const glm::dvec3& v);
// vee of the antisymmetric part: the vector v with hat(v) = (M - M^T) / 2 (vee(hat(v)) == v exactly).
// For a rotation by angle t about the unit axis u this is sin(t) * u.
glm::dvec3 vee(const glm::dmat3& M);

// exp: Rodrigues vector -> rotation matrix (Rodrigues' formula with sin(t)/t and
// (1 - cos t)/t^2, Taylor-expanded below |r| = 1e-6).
glm::dmat3 exp(const glm::dvec3& r);
// log: rotation matrix -> Rodrigues vector with |r| <= pi, through the unit quaternion;
// canonical at pi (see above).
glm::dvec3 log(const glm::dmat3& R);
// Angle of a rotation matrix, in [0, pi]: |log(R)|.
double angle(const glm::dmat3& R);

// Angle of a rotation matrix, in [0, pi], as atan2(|vee(R)|, (trace - 1) / 2): accurate
// near 0 and near pi, where acos of the trace loses half the digits (the evaluation's metric).
double angle_sincos(const glm::dmat3& R);
// The Rodrigues vector of R from angle_sincos and the axis vee(R) / sin(angle); near pi,
// where vee(R) vanishes, the dominant column of (R + I) / 2 = u u^T, signed by vee(R).
// |r| <= pi; at exactly pi the sign is not canonical (unlike log).
glm::dvec3 log_sincos(const glm::dmat3& R);
// The angle whose cosine is (trace - 1) / 2, for when only a trace is known; the
// cosine is clamped to [-1, 1] against rounding.
double angle_from_trace(double trace);

// Rotation by `angle` about z (exp of (0, 0, angle)).
glm::dmat3 about_z(double angle);
// A vector turned by `angle` about `unit_axis` (Rodrigues' rotation formula on the vector itself, as the simulator
// turns the sensor and its errors): v cos a + (k x v) sin a + k (k . v)(1 - cos a).
glm::dvec3 rotate(const glm::dvec3& v, double angle, const glm::dvec3& unit_axis);
// Rotation by `angle` about the unit vector `axis` in closed form:
// cos(a) I + sin(a) hat(axis) + (1 - cos(a)) axis axis^T.
glm::dmat3 about_axis(const glm::dvec3& axis, double angle);

// The nearest rotation to a matrix that is almost one (Gram-Schmidt on the columns).
glm::dmat3 orthonormalize(const glm::dmat3& M);
// A rotation as an input check means it: finite, orthonormal to 1e-6 in every entry of
// R^T R - I (|entry| < 1e-6), and proper (det > 0; a reflection is rejected).
bool is_rotation(const glm::dmat3& R);

}  // namespace sva::so3
