#pragma once
// A reading as the recogniser sees it, in one form: where it was taken, its normal, normConf and soft appearance
// classes. A raw sva::Reading becomes one here, checked once (describe_reading), and enters the pose grid's frame
// through to_grid; the filter, the estimate's stages and the planner start from it and check nothing again.
#include <sva/reading.hpp>

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "appearance/appearance_model.hpp"
#include "map/pair_map.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct ObservedReading {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  float norm_conf = 0.0f;
  std::vector<ClassWeight> classes;  // Eq 12: non-empty, weights sum to 1
  // The pad as it pressed: its x axis (rows run along normal x x_axis) and its image as penetration, mm per element
  // (the pressure over the sensor's stiffness, row-major), which the measurement model compares with a hypothesis's
  // surface under the pad. Empty when the reading came without an image (a planner's prediction, one made by hand).
  glm::dvec3 x_axis{1.0, 0.0, 0.0};
  std::vector<float> depth_mm;
};

// From a raw reading to what the filter sees (robot frame): refuses readings the controller did not converge on,
// images of the wrong size or with non-finite values, describes the image with the map's appearance model
// (descriptor, soft classes, normConf) and checks the description (validated). Throws sva::Error starting with
// `what` (e.g. "reading 3") on bad input.
ObservedReading describe_reading(const PairMap& map, const Reading& reading, const std::string& what);

// Checks an observed reading against a map (finite geometry, a normal of some length, classes the map knows);
// throws sva::Error naming `what` and the fault. Returns the reading with its normal normalised and its weights
// renormalised. describe_reading calls it; so do tests and tools that make observed readings by hand.
ObservedReading validated(const ObservedReading& r, const PairMap& map, const char* what);

// A checked reading in the pose grid's frame: the belief and the fine pose never see the robot frame. The normal
// and the weights are normalised again after the rotation, as the filter has always received them (the golden
// digests of datasets, maps and evaluations hold these bits).
ObservedReading to_grid(const PoseSpace& space, ObservedReading r);

}  // namespace sva
