#include "backends/cpu/belief_shard.hpp"

#include <algorithm>

#include "belief/belief_math.hpp"
#include "votes/pose_space.hpp"

namespace sva {

BeliefShard::BeliefShard(std::uint32_t objects, std::uint32_t mass_bits, std::size_t expected)
    : mass_bits_(mass_bits),
      // sva_exp2_neg_units(d, mass_bits) is 0 from d = (mass_bits + 1) 2^32 on.
      band_width_((std::uint64_t{mass_bits} + 1) << 32),
      offset_(expected),
      band_(expected / 4) {
  touched_.assign(objects, 0);
  best_offset_.assign(objects, 0);
  best_key_.assign(objects, 0);
}

void BeliefShard::reset() {
  drop_upper();
  offset_.clear_keeping_capacity();
  band_.clear_keeping_capacity();
  band_pruned_size_ = 0;
  band_pruned_max_ = 0;
  max_ = 0;
  std::fill(touched_.begin(), touched_.end(), 0);
  std::fill(best_offset_.begin(), best_offset_.end(), 0);
  std::fill(best_key_.begin(), best_key_.end(), 0);
}

void BeliefShard::add(std::span<const BinOffset> terms, std::uint32_t count) {
  if (terms.empty() || count == 0) return;
  // The offset table outgrows the caches, so nearly every addition misses. An addition's probe loop branches on the
  // key it loads, and a mispredicted exit waits for the miss: added one after another, the terms missed one at a
  // time. Their home slots are loaded a batch ahead instead, as independent loads whose misses overlap (prefetch
  // instructions did not help on the development machine; docs/recognition.md, "The floor of the tables").
  for_each_loaded(
      offset_, terms, [](const BinOffset& t) { return t.key; }, [&](const BinOffset& t) { add_term(t, count); });
  // The band is pruned as it grows, and as it goes stale: once the maximum has risen by the band's width since the
  // last prune, every bin the band held then has left it unless added since. A belief that sharpens (flat over a
  // session's first readings, then one peak) otherwise kept the stale bins of its flat phase for good, and every
  // estimate read them: at 30 paper3d readings, 13,000-52,000 entries for 32-60 bins in the band.
  constexpr std::size_t kStaleFloor = 128;  // a band this small is read in a moment: not worth a prune
  const bool grown = band_.size() > 2 * std::max<std::size_t>(band_pruned_size_, 1024);
  const bool stale = max_ - band_pruned_max_ >= band_width_ && band_.size() > kStaleFloor;
  if (grown || stale) prune_band();
}

void BeliefShard::add_term(const BinOffset& t, std::uint32_t count) {
  bool inserted = false;
  const std::uint64_t added = t.offset * count;
  const std::uint64_t off = offset_.add_get(t.key, added, &inserted);
  note(t.key, off, inserted);
  // A bin that crosses the upper set's floor joins it (its offset is read from the table when asked).
  if (off >= upper_floor_ && off - added < upper_floor_ && upper_floor_ != 0) upper_.set(t.key, 0);
}

// Keeps the reductions current after bin `key` rose to `offset`.
void BeliefShard::note(std::uint64_t key, std::uint64_t offset, bool inserted) {
  const std::uint32_t o = PoseSpace::object_of(key);
  if (inserted) ++touched_[o];
  if ((inserted && touched_[o] == 1) || offset > best_offset_[o] || (offset == best_offset_[o] && key < best_key_[o])) {
    best_offset_[o] = offset;
    best_key_[o] = key;
  }
  max_ = std::max(max_, offset);
  if (in_band(offset, max_)) band_.set(key, offset);
}

void BeliefShard::prune_band() {
  std::size_t keeping = 0;  // sized for what it keeps, as forget_below's table
  band_.for_each([&](std::uint64_t, std::uint64_t off) { keeping += in_band(off, max_); });
  BeliefTable kept(keeping);
  band_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (in_band(off, max_)) kept.set(key, off);
  });
  band_ = std::move(kept);
  band_pruned_size_ = band_.size();
  band_pruned_max_ = max_;
}

std::size_t BeliefShard::forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) {
  drop_upper();  // its bins may be forgotten
  // Sized for what it keeps (a half load), not for what it held: a session's table between updates is the larger
  // part of its memory in a batch, and the bins it forgot were most of it. The kept keys are looked up, not searched
  // for each bin: they are a few thousand, the bins hundreds of thousands.
  std::size_t keeping = keep.size();
  offset_.for_each([&](std::uint64_t, std::uint64_t off) { keeping += off >= below; });
  BeliefTable kept(keeping);
  offset_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (off >= below) kept.set(key, off);
  });
  for (const std::uint64_t key : keep) {
    std::uint64_t off = 0;
    if (offset_.find(key, &off) && off < below) kept.set(key, off);
  }
  const std::size_t forgotten = offset_.size() - kept.size();
  retired_allocations_ += offset_.allocations();
  offset_ = std::move(kept);
  recount();
  return forgotten;
}

// The reductions made again from the table after forgetting: the belief's floor is the whole belief's, so this
// shard may have forgotten its own maximum and an object's best bin, and its band may hold forgotten bins.
void BeliefShard::recount() {
  max_ = 0;
  std::fill(touched_.begin(), touched_.end(), 0);
  offset_.for_each([&](std::uint64_t key, std::uint64_t off) {
    const std::uint32_t o = PoseSpace::object_of(key);
    if (++touched_[o] == 1 || off > best_offset_[o] || (off == best_offset_[o] && key < best_key_[o])) {
      best_offset_[o] = off;
      best_key_[o] = key;
    }
    max_ = std::max(max_, off);
  });
  for (std::size_t o = 0; o < touched_.size(); ++o)
    if (touched_[o] == 0) best_offset_[o] = best_key_[o] = 0;
  band_.clear();
  offset_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (in_band(off, max_)) band_.set(key, off);
  });
  prune_band();  // sized for what it holds
}

void BeliefShard::add_band_mass(std::uint64_t max, std::vector<std::uint64_t>* mass) const {
  band_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (in_band(off, max)) (*mass)[PoseSpace::object_of(key)] += belief_math::sva_exp2_neg_units(max - off, mass_bits_);
  });
}

namespace {

// The best `k` bins that `each_bin` gives (it calls its argument with every bin's key and offset) and that pass
// `keep`, best first, through a bounded heap (worst on top): one pass, no copy of the bins. *passed counts the bins
// that pass.
template <class EachBin, class Keep>
std::vector<BinOffset> best_of(EachBin&& each_bin, std::size_t k, Keep keep, std::size_t* passed) {
  std::vector<BinOffset> heap;
  heap.reserve(k);
  *passed = 0;
  each_bin([&](std::uint64_t key, std::uint64_t off) {
    if (!keep(off)) return;
    ++*passed;
    const BinOffset b{key, off};
    if (heap.size() < k) {
      heap.push_back(b);
      std::push_heap(heap.begin(), heap.end(), better_bin);
    } else if (better_bin(b, heap.front())) {
      std::pop_heap(heap.begin(), heap.end(), better_bin);
      heap.back() = b;
      std::push_heap(heap.begin(), heap.end(), better_bin);
    }
  });
  std::sort_heap(heap.begin(), heap.end(), better_bin);
  return heap;
}

}  // namespace

std::vector<BinOffset> BeliefShard::band_top(std::size_t n) const {
  std::size_t in_band_bins = 0;
  return best_of([&](auto&& fn) { band_.for_each(fn); }, n, [&](std::uint64_t off) { return in_band(off, max_); },
                 &in_band_bins);
}

std::vector<BinOffset> BeliefShard::top(std::size_t k) const {
  std::size_t in_band_bins = 0;
  std::vector<BinOffset> best = best_of([&](auto&& fn) { band_.for_each(fn); }, k,
                                        [&](std::uint64_t off) { return in_band(off, max_); }, &in_band_bins);
  // Every bin outside the band lies below every bin in it: the band holds the top k unless it has fewer than k
  // bins. A sharp belief asked past its band (an estimate's next modes) takes the whole table, in place.
  if (in_band_bins < k && in_band_bins < offset_.size()) return best_past_band(k);
  return best;
}

void BeliefShard::drop_upper() const {
  upper_floor_ = 0;
  upper_made_size_ = 0;
  upper_.clear_keeping_capacity();  // as the other tables: a reset keeps the allocation for the next session
}

std::vector<BinOffset> BeliefShard::best_past_band(std::size_t k) const {
  constexpr std::size_t kGrowth = 8;
  const std::size_t wide = 4 * k;
  // A kept set grown eightfold is cut back to its own best 4k: it holds every bin above its floor, so its best are the
  // table's, and no pass over the table is needed (before, such a set was dropped and the table passed again: 169 of
  // 233 passes in a bench at 30 paper3d readings, each a walk through tens of MB of a session's belief).
  if (upper_floor_ != 0 && upper_.size() > kGrowth * upper_made_size_) keep_upper(upper_best(wide), wide);
  // A kept upper set answers while it holds k bins: every bin outside it lies below its floor, below them all.
  if (upper_floor_ != 0 && upper_.size() >= k) return upper_best(k);
  // A pass over the table for 4k bins.
  std::size_t passed = 0;
  std::vector<BinOffset> best =
      best_of([&](auto&& fn) { offset_.for_each(fn); }, wide, [](std::uint64_t) { return true; }, &passed);
  keep_upper(best, wide);
  best.resize(std::min(k, best.size()));
  return best;
}

std::vector<BinOffset> BeliefShard::upper_best(std::size_t n) const {
  // Each kept bin's offset as it is now, read in place (asked again and again as a merge grows its request).
  const auto each_upper = [&](auto&& fn) {
    upper_.for_each([&](std::uint64_t key, std::uint64_t) { fn(key, offset_.get(key)); });
  };
  std::size_t passed = 0;
  return best_of(
      each_upper, n, [](std::uint64_t) { return true; }, &passed);
}

void BeliefShard::keep_upper(const std::vector<BinOffset>& best, std::size_t wide) const {
  // Those above the wide-th best's offset become the upper set (equal offsets at the edge stay out, so that every bin
  // outside lies strictly below the floor); with fewer than `wide` bins none is kept.
  drop_upper();
  if (best.size() != wide || !(best.back().offset + 1 > best.back().offset)) return;
  upper_floor_ = best.back().offset + 1;
  for (const BinOffset& b : best)
    if (b.offset >= upper_floor_) upper_.set(b.key, 0);
  upper_made_size_ = std::max<std::size_t>(upper_.size(), 1);
}

}  // namespace sva
