#include "planning/contact_classes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace sva::planning {

namespace {

// Row `mass` (one weight per class) normalised, classes below a thousandth of the row's total dropped (rounding
// dust from float weights), or empty when the row holds nothing.
std::vector<ClassWeight> normalised(const double* mass, std::uint32_t classes) {
  double total = 0.0;
  for (std::uint32_t c = 0; c < classes; ++c) total += mass[c];
  std::vector<ClassWeight> out;
  if (!(total > 0.0)) return out;
  double kept = 0.0;
  for (std::uint32_t c = 0; c < classes; ++c)
    if (mass[c] >= 1e-3 * total) kept += mass[c];
  for (std::uint32_t c = 0; c < classes; ++c)
    if (mass[c] >= 1e-3 * total) out.push_back({c, static_cast<float>(mass[c] / kept)});
  return out;
}

// Readings without classes of their own take those of the nearest reading of their object that has some (brute
// force per object: the planner is built once per map, and a surface contact has a few hundred paired neighbours).
void classes_from_nearest(const MapReadings& rd, std::vector<std::vector<ClassWeight>>& out) {
  std::vector<std::size_t> first{0};
  for (std::size_t r = 1; r < rd.size(); ++r)
    if (rd.object[r] != rd.object[r - 1]) first.push_back(r);
  first.push_back(rd.size());
  for (std::size_t g = 0; g + 1 < first.size(); ++g) {
    std::vector<std::size_t> paired;
    for (std::size_t r = first[g]; r < first[g + 1]; ++r)
      if (!out[r].empty()) paired.push_back(r);
    if (paired.empty()) continue;
    for (std::size_t r = first[g]; r < first[g + 1]; ++r) {
      if (!out[r].empty()) continue;
      std::size_t best = paired.front();
      float best_d = std::numeric_limits<float>::infinity();
      for (std::size_t q : paired) {
        const float dx = rd.px[q] - rd.px[r], dy = rd.py[q] - rd.py[r], dz = rd.pz[q] - rd.pz[r];
        const float d = dx * dx + dy * dy + dz * dz;
        if (d < best_d) best_d = d, best = q;
      }
      out[r] = out[best];
    }
  }
}

}  // namespace

std::vector<std::vector<ClassWeight>> contact_classes(const PairMap& map) {
  const std::size_t n = map.readings.size();
  const std::uint32_t k = map.key_space.n_classes, bins = map.key_space.n_dist_bins;
  std::vector<std::vector<ClassWeight>> out(n);
  if (k == 0 || bins == 0) return out;
  std::vector<double> mass(n * k, 0.0);
  for (std::size_t i = 0; i + 1 < map.offsets.size() && i < map.keys.size(); ++i) {
    const std::uint32_t ab = map.keys[i] / bins, ca = ab / k, cb = ab % k;
    for (std::uint32_t e = map.offsets[i]; e < map.offsets[i + 1]; ++e) {
      const double w = map.entry_weight[e];
      if (map.entry_a[e] < n) mass[map.entry_a[e] * k + ca] += w;
      if (map.entry_b[e] < n) mass[map.entry_b[e] * k + cb] += w;
    }
  }
  for (std::size_t r = 0; r < n; ++r) out[r] = normalised(&mass[r * k], k);
  classes_from_nearest(map.readings, out);
  const auto& histogram = map.baseline.class_given_object;
  std::vector<double> uniform(k, 1.0);
  for (std::size_t r = 0; r < n; ++r) {
    if (!out[r].empty()) continue;
    const std::size_t o = map.readings.object[r];
    const bool has_histogram = map.baseline.n_classes == k && (o + 1) * k <= histogram.size();
    out[r] = normalised(has_histogram ? &histogram[o * k] : uniform.data(), k);
  }
  return out;
}

double class_overlap(const std::vector<ClassWeight>& a, const std::vector<ClassWeight>& b) {
  double s = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i].cls < b[j].cls) {
      ++i;
    } else if (b[j].cls < a[i].cls) {
      ++j;
    } else {
      s += std::sqrt(static_cast<double>(a[i].weight) * static_cast<double>(b[j].weight));
      ++i;
      ++j;
    }
  }
  return std::min(s, 1.0);
}

}  // namespace sva::planning
