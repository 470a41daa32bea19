#include "appearance/soft_classes.hpp"

#include <sva/base/portable_math.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "appearance/descriptor.hpp"

namespace sva::appearance {

std::vector<float> cluster_psi(const std::vector<float>& descriptors, const std::vector<float>& medoids,
                               const std::vector<std::uint32_t>& membership, std::uint32_t dim) {
  const std::size_t k = medoids.size() / dim;
  std::vector<double> sum(k, 0.0);
  std::vector<std::size_t> count(k, 0);
  for (std::size_t j = 0; j < membership.size(); ++j) {
    const std::uint32_t i = membership[j];
    assert(i < k);
    const double dev = 1.0 - static_cast<double>(affinity(&descriptors[j * dim], &medoids[i * dim], dim));
    sum[i] += dev * dev;
    ++count[i];
  }
  std::vector<double> psi(k, 0.0), positive;
  for (std::size_t i = 0; i < k; ++i) {
    psi[i] = count[i] ? sum[i] / static_cast<double>(count[i]) : 0.0;
    if (psi[i] > kMinPsi) positive.push_back(psi[i]);
  }
  double floor = kDefaultPsiFloor;
  if (!positive.empty()) {
    std::sort(positive.begin(), positive.end());
    floor = positive[positive.size() / 2];
  }
  std::vector<float> out(k);
  for (std::size_t i = 0; i < k; ++i) out[i] = static_cast<float>(psi[i] > kMinPsi ? psi[i] : floor);
  return out;
}

std::vector<ClassWeight> soft_classes(const float* descriptor, const std::vector<float>& medoids,
                                      const std::vector<float>& psi, std::uint32_t dim, float prune_ratio) {
  const std::size_t k = psi.size();
  assert(k > 0 && medoids.size() == k * dim);
  // Log domain: with small psi every exp() of Eq 8 may underflow, yet the
  // ratios that Eq 9-12 need stay well defined.
  std::vector<double> logp(k);
  double best = -INFINITY;
  for (std::size_t i = 0; i < k; ++i) {
    const double dev = 1.0 - static_cast<double>(affinity(descriptor, &medoids[i * dim], dim));
    const double var = psi[i];
    logp[i] = -0.5 * pmath::log(2.0 * std::numbers::pi * var) - dev * dev / (2.0 * var);
    best = std::max(best, logp[i]);
  }
  // Eq 9 normalises by the same sum for every class, so Eq 11 compares
  // likelihood ratios: keep classes above T_a times the best.
  std::vector<ClassWeight> out;
  double total = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const double rel = pmath::exp(logp[i] - best);
    if (logp[i] == best || rel > prune_ratio) {
      out.push_back({static_cast<std::uint32_t>(i), static_cast<float>(rel)});
      total += rel;
    }
  }
  for (auto& c : out) c.weight = static_cast<float>(c.weight / total);
  return out;
}

}  // namespace sva::appearance
