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
};

struct SimulatedData {
  Dataset train;
  Dataset test;
};

// Loads and validates every mesh of the scene, then runs the scene's protocol.
// Throws sva::Error naming the mesh file and the fault on bad input.
SimulatedData simulate(const Scene& scene, const SimulateOptions& options);

// A contact sheet PNG: tactile images beside their contact locations.
void write_preview(const Dataset& data, const std::filesystem::path& png, int max_readings = 48);

}  // namespace sva::sim
