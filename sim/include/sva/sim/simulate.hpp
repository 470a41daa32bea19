#pragma once
// The Embree tactile simulator: readings of a scene's objects, made the way
// the paper made them (Sec 1.1, 5.1, 5.2). See docs/sensor-model.md.
#include <sva/dataset.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <filesystem>

namespace sva::sim {

struct SimulateOptions {
  int train_per_object = -1;  // -1: the scene protocol's default
  int test_per_object = -1;
  std::uint64_t seed = 1;
  unsigned threads = 0;  // 0: all cores; results do not depend on it
  // Multiplies every sigma and spread of the scene's errors block (the robustness sweep's ladder): 0 is the ideal
  // world, 1 the scene as written. The datasets record the scaled errors.
  double error_scale = 1.0;
};

struct SimulatedData {
  Dataset train;
  Dataset test;
};

// The scene's errors with every sigma and spread (position, normal, gain, offset, noise, crosstalk) times `factor`;
// the full scale stays (a property of the array, not an error), except at 0, the ideal world, which never saturates.
// Throws sva::Error when the factor is negative or not finite, or makes the errors impossible (gain spread above
// 0.3, crosstalk of the 8 neighbours reaching the element's own pressure).
ErrorModel scale_errors(const ErrorModel& errors, double factor);

// Loads and validates every mesh of the scene, then runs the scene's protocol.
// Throws sva::Error naming the mesh file and the fault on bad input.
SimulatedData simulate(const Scene& scene, const SimulateOptions& options);

}  // namespace sva::sim
