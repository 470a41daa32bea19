#pragma once
// The steps of a pose bin's neighbourhood, one home for the host's hypotheses (estimate/hypotheses.cpp) and the
// device's choice of the keys they read (backends/vulkan/gpu_belief.cpp, belief_hoods.comp's axis_steps).
#include <algorithm>
#include <cstdint>

#include "votes/pose_space.hpp"

namespace sva {

// The steps along the planar angle a neighbourhood of `radius` grid steps takes: round the circle, cut to distinct
// bins where the radius would go round it.
inline void angle_steps(const PoseSpace& space, int radius, int* lo, int* hi) {
  const int rb = space.spec().rotation_bins;
  *lo = -std::min(radius, (rb - 1) / 2);
  *hi = std::min(radius, rb - 1 - (rb - 1) / 2);
}

// The bins of a neighbourhood of `radius` grid steps (Chebyshev) about any bin, the grid's edges ignored: the most
// one holds.
inline std::uint64_t neighbourhood_steps(const PoseSpace& space, int radius) {
  const auto side = static_cast<std::uint64_t>(2 * radius + 1);
  if (!space.planar()) return side * side * side * side * side * side;
  int lo = 0, hi = 0;
  angle_steps(space, radius, &lo, &hi);
  return side * side * static_cast<std::uint64_t>(hi - lo + 1);
}

}  // namespace sva
