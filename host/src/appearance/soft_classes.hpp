#pragma once
// Soft appearance classes (paper Eq 7-12). psi_i (Eq 7) is a mean squared
// deviation of the affinity from 1, and we use it consistently as the
// variance of the Gaussian of Eq 8 (normaliser 1 / sqrt(2 pi psi_i)).
#include <cstdint>
#include <vector>

#include "appearance/appearance_model.hpp"

namespace sva::appearance {

// psi floor when psi would otherwise be zero (single-member clusters, or
// clusters whose members all equal the medoid): the median psi of the
// clusters that have a positive one, or kDefaultPsiFloor when none has.
constexpr double kDefaultPsiFloor = 1e-4;
constexpr double kMinPsi = 1e-10;

// Eq 7 for every cluster: descriptors are n x dim (unit rows), medoids k x dim,
// membership[j] the cluster of descriptor j. Floors applied as above.
std::vector<float> cluster_psi(const std::vector<float>& descriptors, const std::vector<float>& medoids,
                               const std::vector<std::uint32_t>& membership, std::uint32_t dim);

// Eq 8-12 for one descriptor against k medoids: classes with weight > 0 in
// increasing class order, weights summing to 1, never empty.
std::vector<ClassWeight> soft_classes(const float* descriptor, const std::vector<float>& medoids,
                                      const std::vector<float>& psi, std::uint32_t dim, float prune_ratio);

}  // namespace sva::appearance
