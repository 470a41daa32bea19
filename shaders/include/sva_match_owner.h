// The owner rule of sva_match_likelihood.h, one text for the CPU reference
// and match_votes.glsl: a map pair is voted by the first of the observed
// pair's key items that holds it, with the likelihood units summed over every
// item that holds it. The includer provides the accessors first:
//   uint sva_item_begin(uint k), sva_item_end(uint k)   entries of key item k: [begin, end)
//   uint sva_item_reversed(uint k)                      1: its entries match with their ends swapped
//   float sva_item_weight(uint k)                       w_obs of key item k
//   uint sva_entry_a(uint e), sva_entry_b(uint e)       map entry e's readings (a < b)
//   float sva_entry_weight(uint e)                      its weight under its key
// (GLSL: functions over the buffers; C++: members of the class that includes
// this file in its body, over the map and the pair's key ranges.)
#ifndef SVA_MATCH_OWNER_H
#define SVA_MATCH_OWNER_H

#define SVA_NO_ENTRY 0xffffffffu

// The entry of key item k holding the map pair whose ends match the observed
// pair's as (ra, rb) (entries sorted by (a, b); a reversed item stores the pair
// as (rb, ra)), or SVA_NO_ENTRY. A bounded binary search.
SVA_FN uint sva_find_in_item(uint k, uint ra, uint rb) {
  uint a = ra;
  uint b = rb;
  if (sva_item_reversed(k) != 0u) {
    a = rb;
    b = ra;
  }
  uint lo = sva_item_begin(k);
  uint hi = sva_item_end(k);
  for (uint step = 0u; step < 33u; ++step) {
    if (lo >= hi) break;
    uint mid = lo + ((hi - lo) >> 1);
    uint ma = sva_entry_a(mid);
    if (ma < a || (ma == a && sva_entry_b(mid) < b)) lo = mid + 1u;
    else hi = mid;
  }
  if (lo < sva_item_end(k) && sva_entry_a(lo) == a && sva_entry_b(lo) == b) return lo;
  return SVA_NO_ENTRY;
}

// The likelihood units of the map pair (ra, rb) found under key item k (of the
// pair's items [first, last)) with entry weight w: 0 when an earlier item holds
// it too (that item votes it), else the sum over k and every later item holding it.
SVA_FN uint64_t sva_owned_likelihood(uint first, uint k, uint last, uint ra, uint rb, float w) {
  for (uint i = first; i < k; ++i)
    if (sva_find_in_item(i, ra, rb) != SVA_NO_ENTRY) return uint64_t(0);
  uint64_t units = sva_likelihood_units(sva_item_weight(k) * w);
  for (uint i = k + 1u; i < last; ++i) {
    uint f = sva_find_in_item(i, ra, rb);
    if (f != SVA_NO_ENTRY) units += sva_likelihood_units(sva_item_weight(i) * sva_entry_weight(f));
  }
  return units;
}

#endif
