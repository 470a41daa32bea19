#pragma once
// A pose bin's neighbourhood (shaders/include/sva_neighbourhood.h) compiled as C++: the steps along each grid axis and
// the radius test, one text for the host's hypotheses (estimate/hypotheses.cpp) and the device's choice of the keys
// they read (backends/vulkan/gpu_belief.cpp, belief_hoods.comp).
#include <cstdint>

#include <glm/glm.hpp>

#include "votes/pose_space.hpp"

namespace sva {

namespace hood_math {
using glm::abs;
using glm::min;
using uint = std::uint32_t;
#include "sva_neighbourhood.h"
}  // namespace hood_math

// The first and last step along axis a (0-2 translation, 3-5 rotation) of a neighbourhood of `radius` grid steps.
inline int hood_step_lo(const PoseSpace& space, std::uint32_t a, int radius) {
  return hood_math::sva_hood_step_lo(a, radius, space.planar(), space.spec().rotation_bins);
}
inline int hood_step_hi(const PoseSpace& space, std::uint32_t a, int radius) {
  return hood_math::sva_hood_step_hi(a, radius, space.planar(), space.spec().rotation_bins);
}

// The bins of a neighbourhood of `radius` grid steps about any bin, the grid's edges ignored: the most one holds.
inline std::uint64_t neighbourhood_steps(const PoseSpace& space, int radius) {
  std::uint64_t n = 1;
  for (std::uint32_t a = 0; a < 6; ++a)
    n *= static_cast<std::uint64_t>(hood_step_hi(space, a, radius) - hood_step_lo(space, a, radius) + 1);
  return n;
}

// Two bins of one object within `radius` steps along every axis (the planar angle round the circle).
inline bool within_steps(const BinIndex& a, const BinIndex& b, const PoseSpace& space, int radius) {
  if (a.object != b.object) return false;
  for (std::uint32_t k = 0; k < 6; ++k) {
    const int d = k < 3 ? a.t[k] - b.t[k] : a.r[k - 3] - b.r[k - 3];
    if (!hood_math::sva_hood_axis_within(k, d, radius, space.planar(), space.spec().rotation_bins)) return false;
  }
  return true;
}

}  // namespace sva
