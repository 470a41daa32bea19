#pragma once
// SO(3) helpers in double for the host side of recognition (bin centres, the
// refined estimate, tests): the exponential map from a Rodrigues vector
// (axis * angle) and its inverse, canonical at angle pi. The float versions
// that decide bins live in sva_vote_math.h.
#include <glm/glm.hpp>

namespace sva::rotation {

// exp: Rodrigues vector -> rotation matrix.
glm::dmat3 exp(const glm::dvec3& r);
// log: rotation matrix -> Rodrigues vector with |r| <= pi. At |r| = pi, where
// r and -r are the same rotation, the largest-magnitude component is positive
// (the same rule as sva_quat_to_rodrigues).
glm::dvec3 log(const glm::dmat3& R);
// Angle of a rotation matrix, in [0, pi].
double angle(const glm::dmat3& R);
// Rotation by `angle` about z.
glm::dmat3 about_z(double angle);
// The nearest rotation to a matrix that is almost one (re-orthonormalised).
glm::dmat3 orthonormalize(const glm::dmat3& M);
// A rotation as an input check means it: finite, orthonormal to 1e-6 in every entry of R^T R - I, and proper.
bool is_rotation(const glm::dmat3& R);

}  // namespace sva::rotation
