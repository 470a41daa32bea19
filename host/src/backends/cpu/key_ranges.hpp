#pragma once
// One observed pair's matches (sva_match_likelihood.h): the map entries under the pair's keys, each distinct map
// pair once, with the likelihood units summed over every key that holds it. Two ways to the same answer:
//  - OwnerRule: the shared text sva_match_owner.h, which match_votes.glsl runs too: each entry binary-searches the
//    pair's other key ranges (a GPU thread per entry has nothing better);
//  - for_each_match: what the CPU reference runs. A key's entries are sorted by (reading a, reading b), so one
//    merge over the ranges meets every map pair with all of its holders together, reading each range once, in order.
//    The owner (the first range, in the pair's key order, holding the pair) and the integer sum are the rule's;
//    tests/backends/cpu/test_key_ranges.cpp compares the two.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "map/pair_map.hpp"
#include "votes/vote_math.hpp"

namespace sva::cpu {

// The map entries stored under one of an observed pair's keys.
struct KeyRange {
  std::uint32_t begin, end;
  float weight;   // w_obs of the key
  bool reversed;  // the entries' ends are swapped to match the observed pair (PairKeyWeight::reversed)
};

// The owner rule of sva_match_likelihood.h over one observed pair's key ranges: the text of sva_match_owner.h,
// compiled as members over the map and the ranges.
class OwnerRule {
 public:
  OwnerRule(const PairMap& map, const std::vector<KeyRange>& ranges) : map_(map), ranges_(ranges) {}
  using uint = std::uint32_t;
  using uint64_t = std::uint64_t;

#include "sva_match_owner.h"

 private:
  uint sva_item_begin(uint k) const { return ranges_[k].begin; }
  uint sva_item_end(uint k) const { return ranges_[k].end; }
  uint sva_item_reversed(uint k) const { return ranges_[k].reversed ? 1u : 0u; }
  float sva_item_weight(uint k) const { return ranges_[k].weight; }
  uint sva_entry_a(uint e) const { return map_.entry_a[e]; }
  uint sva_entry_b(uint e) const { return map_.entry_b[e]; }
  float sva_entry_weight(uint e) const { return map_.entry_weight[e]; }
  static uint64_t sva_likelihood_units(float w) { return vote_math::sva_likelihood_units(w); }

  const PairMap& map_;
  const std::vector<KeyRange>& ranges_;
};

// Calls fn(entry, ra, rb, units) once per distinct map pair under the ranges: `entry` is the owner's entry, (ra, rb)
// the map pair's readings in the observed pair's order, `units` sva_owned_likelihood's sum. A map pair held with
// its ends swapped (a reversed range) has ra > rb, one held as stored ra < rb (entries keep a < b): the two kinds
// never meet, so each is merged on its own. The matches come in (orientation, a, b) order, not the rule's.
template <class Fn>
void for_each_match(const PairMap& map, const std::vector<KeyRange>& ranges, Fn&& fn) {
  struct Cursor {
    std::uint32_t at, end;
    float weight;
  };
  std::vector<Cursor> live;
  live.reserve(ranges.size());
  const auto pair_at = [&](std::uint32_t e) { return (std::uint64_t{map.entry_a[e]} << 32) | map.entry_b[e]; };
  for (const bool reversed : {false, true}) {
    live.clear();
    for (const KeyRange& r : ranges)  // in the pair's key order: the first holder is the owner
      if (r.reversed == reversed && r.begin < r.end) live.push_back({r.begin, r.end, r.weight});
    while (!live.empty()) {
      std::uint64_t lowest = ~std::uint64_t{0};
      for (const Cursor& c : live) lowest = std::min(lowest, pair_at(c.at));
      std::uint32_t owner = 0;
      bool owned = false;
      std::uint64_t units = 0;
      for (Cursor& c : live) {
        if (pair_at(c.at) != lowest) continue;
        if (!owned) owner = c.at, owned = true;
        units += vote_math::sva_likelihood_units(c.weight * map.entry_weight[c.at]);
        ++c.at;
      }
      std::erase_if(live, [](const Cursor& c) { return c.at == c.end; });
      const std::uint32_t a = map.entry_a[owner], b = map.entry_b[owner];
      fn(owner, reversed ? b : a, reversed ? a : b, units);
    }
  }
}

// The map entries the ranges hold: the matches a pair will align, before the owner rule and the cutoffs.
inline std::uint64_t map_entries(const std::vector<KeyRange>& ranges) {
  std::uint64_t n = 0;
  for (const KeyRange& r : ranges) n += r.end - r.begin;
  return n;
}

// One observed pair's ranges cut into up to `pieces` pieces of about equal entries, so that a pair many times the
// others' size can vote on several workers: piece j holds, under each range (in the same key order), the entries whose
// first reading as stored lies in its interval of readings. Every holder of a map pair stores it as (a, b) with a < b
// (for_each_match above), so a map pair's holders all fall in one piece: the owner and the summed units within it are
// the whole pair's, and the pieces' matches together are the pair's. The cuts are the longest range's quantiles of
// first readings; pieces left without entries are dropped (one reading's entries stay whole, so there may be fewer).
inline std::vector<std::vector<KeyRange>> split_by_first_reading(const PairMap& map,
                                                                 const std::vector<KeyRange>& ranges,
                                                                 std::size_t pieces) {
  const auto longest = std::max_element(ranges.begin(), ranges.end(), [](const KeyRange& x, const KeyRange& y) {
    return x.end - x.begin < y.end - y.begin;
  });
  std::vector<std::uint32_t> cuts;  // the first reading of every piece after the first, increasing
  if (longest != ranges.end() && longest->end > longest->begin)
    for (std::size_t j = 1; j < pieces; ++j) {
      const std::uint64_t at = longest->begin + (std::uint64_t{longest->end - longest->begin} * j) / pieces;
      const std::uint32_t a = map.entry_a[at];
      if (a > map.entry_a[longest->begin] && (cuts.empty() || a > cuts.back())) cuts.push_back(a);
    }
  std::vector<std::vector<KeyRange>> out(cuts.size() + 1, ranges);
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const auto first = map.entry_a.begin();
    std::uint32_t from = ranges[k].begin;
    for (std::size_t j = 0; j < cuts.size(); ++j) {
      const auto to =
          static_cast<std::uint32_t>(std::lower_bound(first + from, first + ranges[k].end, cuts[j]) - first);
      out[j][k].begin = from, out[j][k].end = to;
      from = to;
    }
    out.back()[k].begin = from;
  }
  std::erase_if(out, [](const std::vector<KeyRange>& piece) { return map_entries(piece) == 0; });
  return out;
}

}  // namespace sva::cpu
