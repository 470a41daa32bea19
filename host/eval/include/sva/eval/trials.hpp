#pragma once
// Recognition trials (paper Sec 5): each trial takes one object (trials cycle
// through the objects, so N = repetitions x objects), draws a random object
// pose from the pose space and presents that object's converged test readings,
// transformed by the pose, in random order. Every trial draws from its own
// random stream util::Rng(seed, trial), so a trial is the same whichever
// thread builds it and in whatever order.
#include <sva/dataset.hpp>
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include <sva/base/rng.hpp>

namespace sva::eval {

// Poses and moved readings are drawn as the core draws them for the calibration's sessions
// (host/src/training/session_sampling.hpp: sva::random_pose, sva::transform_reading).

struct Trial {
  std::size_t index = 0;
  std::uint32_t object = 0;
  RigidPose pose;                    // true object pose
  std::vector<std::size_t> samples;  // dataset sample index of each reading, in order
  std::vector<Reading> readings;     // transformed by `pose`, in presentation order
};

class TrialGenerator {
 public:
  // Validates the test set: it must hold converged readings of every object
  // of its scene, all finite, with images of the scene's sensor size; errors
  // name `source` (the file) and the fault. max_readings must be >= 1.
  TrialGenerator(const Dataset& test, const PoseSpaceSpec& space, std::uint64_t seed, std::size_t max_readings,
                 std::string source = "test set");

  // Trial t: object t mod objects, pose and reading order from Rng(seed, t).
  // The first min(M, count) readings are distinct (a random permutation);
  // beyond the count they are drawn uniformly with replacement.
  Trial make(std::size_t t) const;

  std::size_t object_count() const { return by_object_.size(); }
  std::size_t readings_of(std::uint32_t object) const { return by_object_[object].size(); }
  // The converged test samples of an object (dataset indices), and a sample's reading in its object's frame
  // (the adaptive policies pick readings by where they lie on the object).
  const std::vector<std::size_t>& samples_of(std::uint32_t object) const { return by_object_[object]; }
  const Reading& object_frame(std::size_t sample) const { return object_frame_[sample]; }

 private:
  const Dataset& test_;
  PoseSpaceSpec space_;
  std::uint64_t seed_;
  std::size_t max_readings_;
  std::vector<std::vector<std::size_t>> by_object_;  // converged sample indices per object
  std::vector<Reading> object_frame_;                // every sample's reading in the object frame
};

}  // namespace sva::eval
