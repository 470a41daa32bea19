// The likelihood of one match (paper Eq 15): an observed pair and a map pair
// of the same object meet under every key they share (soft classes, Eq 7-12,
// and the distance interpolation, Eq 13, put one training pair under several
// keys), and the match's likelihood is the sum over those keys of
// w_obs(key) * w_map(key). The match is aligned and casts its beta samples once,
// with that sum, by its *owner*: the first of the observed pair's keys (in the
// pair's key order) under which the map pair is stored. Entries under a key are
// sorted by (reading a, reading b), so finding a map pair under another key is a
// binary search; the CPU reference and match_votes.comp both follow this rule.
//
// The sum is taken in fixed point (2^-40 units, each term rounded to nearest):
// integer sums do not depend on the order of the keys, so the reversed observed
// pair (whose keys come in another order) gets bit for bit the same likelihood.
#ifndef SVA_MATCH_LIKELIHOOD_H
#define SVA_MATCH_LIKELIHOOD_H

#include "sva_fast_math.h"

#define SVA_LIKELIHOOD_UNITS_PER_ONE 1099511627776.0f
#define SVA_LIKELIHOOD_UNIT 9.094947017729282e-13f  // 2^-40, exactly

// A 64-bit unsigned integer from and to its two 32-bit words. The likelihood
// units are built and read through these, in 32-bit integer operations only:
// on an NVIDIA H200 (driver 580) the vote kernel's 64-bit mask in the units'
// conversion to float gave a likelihood rounded up to a whole 2^23 units
// (docs/vulkan-backend.md, "The second GPU run"), while the same text in a
// smaller kernel did not.
#ifdef __cplusplus
SVA_FN uint64_t sva_u64_of_words(uint hi, uint lo) { return (uint64_t(hi) << 32) | uint64_t(lo); }
SVA_FN uint sva_u64_hi(uint64_t x) { return uint(x >> 32); }
SVA_FN uint sva_u64_lo(uint64_t x) { return uint(x & 0xffffffffu); }
#else
uint64_t sva_u64_of_words(uint hi, uint lo) { return packUint2x32(uvec2(lo, hi)); }
uint sva_u64_hi(uint64_t x) { return unpackUint2x32(x).y; }
uint sva_u64_lo(uint64_t x) { return unpackUint2x32(x).x; }
#endif

// One key's term w_obs * w_map (in [0, 1]) in likelihood units; NaN and
// negatives give 0. The whole units r (a float, at most 2^40) split exactly
// into words: r / 2^32 and its floor are exact (a power of two, at most 256),
// and r - hi * 2^32 keeps r's low significand bits, exact below 2^32.
SVA_FN uint64_t sva_likelihood_units(float w) {
  SVA_PRECISE float v = (w > 0.0f ? min(w, 1.0f) : 0.0f) * SVA_LIKELIHOOD_UNITS_PER_ONE;
  SVA_PRECISE float r = SVA_ROUND_UNITS(v);
  SVA_PRECISE float top = floor(r * 2.3283064365386963e-10f);  // 2^-32
  SVA_PRECISE float low = r - top * 4294967296.0f;
  return sva_u64_of_words(uint(top), uint(low));
}

// The summed likelihood as the float the votes are scaled by. The sum stays
// below 2^47 units (fewer than 128 keys of weight <= 1): its bits from 2^24 up
// and its low 24 bits each convert to float exactly, and the one rounding is
// the correctly rounded addition: the same float on every device, whatever
// its integer conversions do.
SVA_FN float sva_likelihood_of_units(uint64_t units) {
  uint hi = sva_u64_hi(units);
  uint lo = sva_u64_lo(units);
  SVA_PRECISE float top = float((hi << 8u) | (lo >> 24u)) * 16777216.0f;
  SVA_PRECISE float low = float(lo & 0xffffffu);
  SVA_PRECISE float l = (top + low) * SVA_LIKELIHOOD_UNIT;
  return l;
}

#endif
