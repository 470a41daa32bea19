#pragma once
// The pair-key stage (paper Eq 13, 15): a pair of readings is looked up, and
// stored, under every key (class of a, class of b, distance bin) its soft
// classes and the distance interpolation give, with the weight
// Pa(ca) Pb(cb) Pd(d). One function serves the map builder (training pairs),
// the Bayes filter (observed pairs) and, through the filter's VoteBatch, the
// GPU's key expansion: the map and the queries cannot disagree on a key or a
// weight.
#include <cstdint>
#include <span>

#include "appearance/appearance_model.hpp"

namespace sva {

// Largest key space (classes^2 x distance bins) a map may have: keeps keys in
// 32 bits and the builder's count tables bounded.
inline constexpr std::uint64_t kMaxPairKeySpace = 1ull << 26;

// Key packing: key = (class_a * n_classes + class_b) * n_dist_bins + dist_bin.
struct PairKeySpace {
  std::uint32_t n_classes = 0;
  std::uint32_t n_dist_bins = 0;
  std::uint32_t pack(std::uint32_t ca, std::uint32_t cb, std::uint32_t d) const {
    return (ca * n_classes + cb) * n_dist_bins + d;
  }
};

// A key a pair is stored or looked up under, with its weight in (0, 1].
// `reversed` (lookups only): the map stores each unordered training pair once,
// as (a, b) with a < b, so an observed pair also looks up its keys with the
// classes swapped, and matches the entries found there with their ends swapped.
struct PairKeyWeight {
  std::uint32_t key;
  float weight;
  std::uint32_t reversed = 0;
};

// Calls emit(PairKeyWeight) for every key of a pair whose first reading has
// soft classes `a`, second `b`, and whose distance falls in `bins`, in a fixed
// order (class of a, class of b, distance bin). The weight is the product of
// the three weights, in that order (so a pair and its reverse get bit-equal
// weights), clamped to 1; keys of weight 0 (or NaN) are skipped.
template <class Emit>
void for_each_pair_key(std::span<const ClassWeight> a, std::span<const ClassWeight> b, std::span<const BinWeight> bins,
                       const PairKeySpace& space, Emit&& emit) {
  for (const ClassWeight& ca : a)
    for (const ClassWeight& cb : b)
      for (const BinWeight& d : bins) {
        const float w = ca.weight * cb.weight * d.weight;
        if (!(w > 0.0f)) continue;
        emit(PairKeyWeight{space.pack(ca.cls, cb.cls, d.bin), w < 1.0f ? w : 1.0f, 0});
      }
}

// The lookups of an observed pair: every key of for_each_pair_key in both
// orientations, the key (ca, cb, d) itself (map pairs (x, y) whose x matches
// the first reading) and the reversed key (cb, ca, d) (map pairs stored as
// (y, x)). Together they find every training pair in either order exactly
// once per key, as the two orders of a map of ordered pairs would.
template <class Emit>
void for_each_query_key(std::span<const ClassWeight> a, std::span<const ClassWeight> b, std::span<const BinWeight> bins,
                        const PairKeySpace& space, Emit&& emit) {
  for_each_pair_key(a, b, bins, space, [&](PairKeyWeight k) {
    emit(k);
    const std::uint32_t d = k.key % space.n_dist_bins, ab = k.key / space.n_dist_bins;
    const std::uint32_t ca = ab / space.n_classes, cb = ab % space.n_classes;
    emit(PairKeyWeight{space.pack(cb, ca, d), k.weight, 1});
  });
}

}  // namespace sva
