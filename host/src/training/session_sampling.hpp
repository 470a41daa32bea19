#pragma once
// How a recognition session is drawn from a set of readings (paper Sec 5): one object, a pose uniform over the
// pose space, that object's readings moved by the pose and shown in random order. The evaluation's trials
// (sva::eval::TrialGenerator) and the calibration's held-out sessions (training/held_out_sessions.hpp) draw
// them alike, from these functions.
#include <sva/pose.hpp>
#include <sva/pose_space.hpp>
#include <sva/reading.hpp>

#include <sva/base/rng.hpp>

namespace sva {

// A rotation uniform on SO(3) (Haar measure), from a uniform unit quaternion.
glm::dmat3 uniform_rotation(util::Rng& rng);

// A pose uniform over the pose space: spatial -> any rotation and a translation uniform in [min, max] per axis;
// planar -> a rotation about z uniform in [-pi, pi) and a translation uniform in [min, max] in x and y.
RigidPose random_pose(util::Rng& rng, const PoseSpaceSpec& space);

// The reading as seen when the object moves by `pose`: position, normal and x axis transformed; the pressure image
// is unchanged.
Reading transform_reading(const Reading& reading, const RigidPose& pose);

}  // namespace sva
