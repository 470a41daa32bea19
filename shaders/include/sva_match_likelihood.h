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

// One key's term w_obs * w_map (in [0, 1]) in likelihood units; NaN and
// negatives give 0.
SVA_FN uint64_t sva_likelihood_units(float w) {
  SVA_PRECISE float v = (w > 0.0f ? min(w, 1.0f) : 0.0f) * SVA_LIKELIHOOD_UNITS_PER_ONE;
  return uint64_t(SVA_ROUND_UNITS(v));
}

// The summed likelihood as the float the votes are scaled by. The sum stays
// below 2^47 units (fewer than 128 keys of weight <= 1), so both halves convert
// to float exactly and the one rounding is the correctly rounded addition:
// the same float on every device, whatever its integer conversions do.
SVA_FN float sva_likelihood_of_units(uint64_t units) {
  SVA_PRECISE float hi = float(uint(units >> 23)) * 8388608.0f;
  SVA_PRECISE float lo = float(uint(units & uint64_t(0x7fffffu)));
  SVA_PRECISE float l = (hi + lo) * SVA_LIKELIHOOD_UNIT;
  return l;
}

#endif
