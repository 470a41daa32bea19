#pragma once
// A dataset: readings of the objects of one scene, with ground truth.
// Binary file format: docs/dataset-format.md.
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/scene.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace sva {

// Where the sensor really was when a reading was taken. The reading holds
// what the robot reported (arm pose errors, the array's errors: see the scene's
// ErrorModel); the simulator knows the truth. Recordings of a real sensor, and
// dataset files of version 1, carry the reading's own pose and no surface normal.
struct SensorTruth {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 x_axis{1.0, 0.0, 0.0};
  glm::dvec3 surface_normal{0.0};  // outward surface normal under the settled array; 0: unknown
};

struct Sample {
  std::uint32_t object = 0;  // which of the scene's objects was touched (ground truth; training labels)
  Reading reading;           // what the sensor gave
  RigidPose object_pose;     // true pose of the object when the reading was taken (identity in simulation)
  SensorTruth truth;         // true sensor pose in the same frame as the reading (before object_pose is applied)
};

struct Dataset {
  Scene scene;        // the scene that produced it (objects, sensor, skin, pose space, defaults)
  std::string split;  // "train", "test" or free text
  std::uint64_t seed = 0;
  std::vector<Sample> samples;

  std::size_t count_converged() const;
};

// The dataset without the named objects (their readings dropped, the others renumbered in order): a map trained on
// it meets the dropped objects as objects "none of these" (`sva train --exclude-objects`, docs/evaluation.md).
// sva::Error for a name the scene does not hold, or when no object would be left.
Dataset without_objects(const Dataset& data, const std::vector<std::string>& names);

void save_dataset(const Dataset& data, const std::filesystem::path& file);
Dataset load_dataset(const std::filesystem::path& file);

}  // namespace sva
