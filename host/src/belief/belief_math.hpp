#pragma once
// The belief's integer arithmetic (shaders/include/sva_belief_math.h) compiled
// as C++, plus the host-side conversions of its parameters.
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include <sva/error.hpp>

#include <sva/base/portable_math.hpp>

namespace sva::belief_math {
using std::uint64_t;
using uint = std::uint32_t;
#include "sva_belief_math.h"

// Belief units per bit of evidence.
constexpr double kUnitsPerBit = static_cast<double>(std::uint64_t{1} << SVA_BELIEF_FRAC_BITS);
// Belief units (offsets, their differences) as bits of evidence.
inline double units_to_bits(std::uint64_t units) { return static_cast<double>(units) / kUnitsPerBit; }
// The smallest eps whose quantisation to 2^-48 stays within 0.5%.
constexpr double kMinEps = 1e-12;

// eps as the fold's integer parameter; throws for eps outside [1e-12, 1).
inline uint64_t eps_units(double eps) {
  if (!std::isfinite(eps) || eps < kMinEps || eps >= 1.0)
    throw Error("recognizer option eps = " + std::to_string(eps) + " must be in [1e-12, 1)");
  return static_cast<uint64_t>(std::llround(std::ldexp(eps, SVA_EPS_FRAC_BITS)));
}

// The most pairs a belief may fold before a bin's offset could pass 2^63
// units: each pair adds at most log2(1 + 1/eps) bits (about 1e8 pairs, 14,000
// readings, at eps = 1e-6).
inline std::uint64_t max_pairs(uint64_t eps_units) {
  const double bits_per_pair =
      pmath::log2(1.0 + std::ldexp(1.0, SVA_EPS_FRAC_BITS) / static_cast<double>(eps_units)) + 1.0;
  return static_cast<std::uint64_t>(std::ldexp(1.0, 63 - SVA_BELIEF_FRAC_BITS) / bits_per_pair);
}

// Fractional bits of the object-mass weights for a pose space with `bins`
// bins per object: every bin weighs at most 2^mass_bits, so an object's mass
// stays below 2^62. Ordinary spaces get all SVA_MAX_MASS_BITS bits (paper3d:
// 6.75 M bins, 39 bits); only absurdly fine grids get fewer.
inline uint mass_bits(uint64_t bins) {
  const int room = 62 - std::bit_width(bins);
  return static_cast<uint>(room < SVA_MAX_MASS_BITS ? (room < 0 ? 0 : room) : SVA_MAX_MASS_BITS);
}

}  // namespace sva::belief_math
