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

struct Sample {
  Reading reading;
  RigidPose object_pose;  // true pose of the object when the reading was taken (identity in simulation)
};

struct Dataset {
  Scene scene;        // the scene that produced it (objects, sensor, skin, pose space, defaults)
  std::string split;  // "train", "test" or free text
  std::uint64_t seed = 0;
  std::vector<Sample> samples;

  std::size_t count_converged() const;
};

void save_dataset(const Dataset& data, const std::filesystem::path& file);
Dataset load_dataset(const std::filesystem::path& file);

}  // namespace sva
