#include "belief/object_mass.hpp"

#include <sva/base/portable_math.hpp>

#include <algorithm>
#include <cassert>

#include "belief/belief_math.hpp"

namespace sva {

// All integer up to the final conversion (each object's sum stays below 2^62).
std::vector<double> object_mass(const BeliefSummary& s, const PoseSpace& space, std::span<const double> weight) {
  const std::uint32_t bits = belief_math::mass_bits(space.bins_per_object());
  const std::uint64_t baseline = belief_math::sva_exp2_neg_units(s.max_offset, bits);
  std::vector<double> mass(space.objects());
  for (std::uint32_t o = 0; o < space.objects(); ++o) {
    assert(s.touched[o] <= space.bins_per_object());
    const std::uint64_t untouched = space.bins_per_object() - s.touched[o];
    mass[o] = static_cast<double>(s.touched_mass[o] + untouched * baseline);
    if (!weight.empty()) mass[o] *= weight[o];
  }
  return mass;
}

// Sub-bin refinement: along each axis of the pose grid, a parabola through the
// log-belief of the best bin and its two neighbours (untouched bins at the

std::vector<double> object_log2_mass(const BeliefSummary& s, const PoseSpace& space) {
  const std::uint32_t bits = belief_math::mass_bits(space.bins_per_object());
  const double max_bits = belief_math::units_to_bits(s.max_offset);
  std::vector<double> out(space.objects());
  for (std::uint32_t o = 0; o < space.objects(); ++o) {
    // The mass in bits relative to a bin at the maximum, as a sum of up to two terms in the log domain: the
    // touched bins (their band sum, or below the band the best bin alone) and the untouched bins at offset 0.
    double terms[2] = {0.0, 0.0};  // at least one is set: an object has touched or untouched bins
    int n = 0;
    if (s.touched_mass[o] > 0)
      terms[n++] = pmath::log2(static_cast<double>(s.touched_mass[o])) - bits;
    else if (s.touched[o] > 0)
      terms[n++] = belief_math::units_to_bits(s.best_offset[o]) - max_bits;
    const std::uint64_t untouched = space.bins_per_object() - s.touched[o];
    if (untouched > 0) terms[n++] = pmath::log2(static_cast<double>(untouched)) - max_bits;
    double top = terms[0];
    for (int i = 1; i < n; ++i) top = std::max(top, terms[i]);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += pmath::exp2(terms[i] - top);
    out[o] = top + pmath::log2(sum);
  }
  return out;
}

double total_mass(const BeliefSummary& summary, const PoseSpace& space, std::span<const double> object_weight) {
  double z = 0.0;
  for (double m : object_mass(summary, space, object_weight)) z += m;
  return z;
}

std::vector<double> object_probability(const BeliefSummary& summary, const PoseSpace& space) {
  std::vector<double> p = object_mass(summary, space);
  double z = 0.0;
  for (double m : p) z += m;
  assert(z > 0.0);  // a bin at the maximum weighs 2^mass_bits >= 1
  for (double& v : p) v /= z;
  return p;
}

}  // namespace sva
