#pragma once
// The vote math's roofline of `sva bench` (bench/roofline/vote_math.glsl): the engine's per-match math alone (the
// alignment, the beta plan, every sample's pose bin and fixed-point mass), without the map, the owner rule or the
// table, once with the engine's exact division and square root and once with the device's own. Beside the bare hash
// scatter it says what bounds the vote kernel on a device (issue 52: the exact math, the owner rule's searches, or
// the table).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "backends/vulkan/context.hpp"

namespace sva::bench {

struct VoteMathRoofline {
  std::size_t matches = 0;
  std::uint64_t samples = 0;        // beta samples worked out (the matches' plans)
  double exact_ms = 0.0;            // best of three; 0 without timestamps
  double device_division_ms = 0.0;  // the same with the device's own division and square root
  bool exact_agrees = false;        // the exact kernel's checksums equal the CPU's, bit for bit
  double exact_samples_per_second() const { return exact_ms > 0 ? 1e3 * static_cast<double>(samples) / exact_ms : 0; }
  double device_division_samples_per_second() const {
    return device_division_ms > 0 ? 1e3 * static_cast<double>(samples) / device_division_ms : 0;
  }
};

// Random matches (an observed and a map pair of similar reach, as the stage tests make them), `floats` per match.
std::vector<float> vote_math_matches(std::size_t matches, std::uint64_t seed);
// The checksums of one match as the kernels write them (3 words), from the engine's math compiled as C++; returns
// its beta samples.
std::uint32_t vote_math_checksum(const float* match, std::uint32_t out[3]);

VoteMathRoofline measure_vote_math(vk::Context& ctx, std::size_t matches);

}  // namespace sva::bench
