#include "backends/cpu/belief.hpp"

#include "backends/cpu/fold_lanes.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "backends/vote_backend.hpp"
#include "belief/belief_math.hpp"

namespace sva {

Belief::Belief(const PoseSpace& space, double eps)
    : space_(&space),
      eps_units_(belief_math::eps_units(eps)),
      mass_bits_(belief_math::mass_bits(space.bins_per_object())),
      // sva_exp2_neg_units(d, mass_bits) is 0 from d = (mass_bits + 1) 2^32 on.
      band_width_((std::uint64_t{mass_bits_} + 1) << 32) {
  reset();
}

void Belief::reset() {
  forget_best();
  drop_upper();
  offset_.clear_keeping_capacity();
  band_.clear_keeping_capacity();
  band_pruned_size_ = 0;
  pairs_ = 0;
  max_ = 0;
  touched_.assign(space_->objects(), 0);
  best_offset_.assign(space_->objects(), 0);
  best_key_.assign(space_->objects(), 0);
}

bool Belief::fold(const PairVotes& votes, std::uint32_t count) {
  assert(votes.keys.size() == votes.mass.size());
  BinAccumulator acc(votes.keys.size());
  for (std::size_t i = 0; i < votes.keys.size(); ++i) acc.add(votes.keys[i], votes.mass[i]);
  return add(terms(acc), count);
}

std::vector<BinOffset> Belief::terms(const BinAccumulator& votes) const {
  std::vector<BinOffset> out;
  terms(votes, &out);
  return out;
}

void Belief::terms(const BinAccumulator& votes, std::vector<BinOffset>* out) const {
  // The worker thread's scratch, kept between pairs: a pair's bins run to tens of thousands, and buffers that size
  // allocated and freed per pair went back to the system and came back as fresh (zeroed, faulted-in) pages.
  thread_local std::vector<std::uint64_t> mass, units;
  out->clear();
  mass.clear();
  std::uint64_t total = 0;  // < 2^63: votes are clamped (SVA_FIXED_MAX_VOTE_UNITS)
  votes.for_each([&](std::uint64_t key, std::int64_t m) {
    if (m <= 0) return;
    out->push_back({key, 0});
    mass.push_back(static_cast<std::uint64_t>(m));
    total += static_cast<std::uint64_t>(m);
  });
  if (total == 0) return;
  units.resize(mass.size());
  cpu::fold_units(mass.data(), mass.size(), total, eps_units_, belief_math::sva_floor_log(total, eps_units_),
                  units.data());
  for (std::size_t i = 0; i < units.size(); ++i) (*out)[i].offset = units[i];
}

bool Belief::add(const std::vector<BinOffset>& terms, std::uint32_t count) {
  if (terms.empty() || count == 0) return false;
  forget_best();
  // The offset table outgrows the caches, so nearly every addition misses. An addition's probe loop branches on the
  // key it loads, and a mispredicted exit waits for the miss: added one after another, the terms missed one at a
  // time. Their home slots are loaded a batch ahead instead, as independent loads whose misses overlap (prefetch
  // instructions did not help on the development machine; docs/recognition.md, "The floor of the tables").
  for_each_loaded(
      offset_, std::span<const BinOffset>(terms), [](const BinOffset& t) { return t.key; },
      [&](const BinOffset& t) { add_term(t, count); });
  pairs_ += count;
  if (band_.size() > 2 * std::max<std::size_t>(band_pruned_size_, 1024)) prune_band();
  return true;
}

void Belief::add_term(const BinOffset& t, std::uint32_t count) {
  bool inserted = false;
  const std::uint64_t added = t.offset * count;
  const std::uint64_t off = offset_.add_get(t.key, added, &inserted);
  note(t.key, off, inserted);
  // A bin that crosses the upper set's floor joins it (its offset is read from the table when asked).
  if (off >= upper_floor_ && off - added < upper_floor_ && upper_floor_ != 0) upper_.set(t.key, 0);
}

// Keeps the reductions current after bin `key` rose to `offset`.
void Belief::note(std::uint64_t key, std::uint64_t offset, bool inserted) {
  const std::uint32_t o = PoseSpace::object_of(key);
  if (inserted) ++touched_[o];
  if ((inserted && touched_[o] == 1) || offset > best_offset_[o] || (offset == best_offset_[o] && key < best_key_[o])) {
    best_offset_[o] = offset;
    best_key_[o] = key;
  }
  max_ = std::max(max_, offset);
  if (in_band(offset)) band_.set(key, offset);
}

void Belief::prune_band() {
  std::size_t keeping = 0;  // sized for what it keeps, as forget_below's table
  band_.for_each([&](std::uint64_t, std::uint64_t off) { keeping += in_band(off); });
  BeliefTable kept(keeping);
  band_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (in_band(off)) kept.set(key, off);
  });
  band_ = std::move(kept);
  band_pruned_size_ = band_.size();
}

std::size_t Belief::forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) {
  forget_best();
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
  std::fill(touched_.begin(), touched_.end(), 0);
  kept.for_each([&](std::uint64_t key, std::uint64_t) { ++touched_[PoseSpace::object_of(key)]; });
  const std::size_t forgotten = offset_.size() - kept.size();
  retired_allocations_ += offset_.allocations();
  offset_ = std::move(kept);
  prune_band();  // its members lie in the band, above `below` (the caller's margin exceeds the band width)
  return forgotten;
}

void Belief::forget_best() {
  std::lock_guard lock(best_.mutex);
  best_.bins.clear();
  best_.asked = 0;
}

BeliefSummary Belief::summarise() const {
  BeliefSummary s;
  s.max_offset = max_;
  s.touched = touched_;
  s.best_offset = best_offset_;
  s.best_key = best_key_;
  s.touched_mass.assign(space_->objects(), 0);
  band_.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (in_band(off))
      s.touched_mass[PoseSpace::object_of(key)] += belief_math::sva_exp2_neg_units(max_ - off, mass_bits_);
  });
  return s;
}

namespace {

bool better(const BinOffset& a, const BinOffset& b) {
  return a.offset != b.offset ? a.offset > b.offset : a.key < b.key;
}

// The best `k` bins of `table` that pass `keep`, best first, through a bounded heap (worst on top): one pass, no
// copy of the table. *passed counts the bins that pass.
template <class Keep>
std::vector<BinOffset> best_of(const BeliefTable& table, std::size_t k, Keep keep, std::size_t* passed) {
  std::vector<BinOffset> heap;
  heap.reserve(k);
  *passed = 0;
  table.for_each([&](std::uint64_t key, std::uint64_t off) {
    if (!keep(off)) return;
    ++*passed;
    const BinOffset b{key, off};
    if (heap.size() < k) {
      heap.push_back(b);
      std::push_heap(heap.begin(), heap.end(), better);
    } else if (better(b, heap.front())) {
      std::pop_heap(heap.begin(), heap.end(), better);
      heap.back() = b;
      std::push_heap(heap.begin(), heap.end(), better);
    }
  });
  std::sort_heap(heap.begin(), heap.end(), better);
  return heap;
}

}  // namespace

std::vector<BinOffset> Belief::best_bins(std::size_t k) const {
  // One estimate asks for the best bins several times (the estimate's top bins, each object's modes, the
  // hypotheses, the surface check's three objects), each a pass over the band: the answer is kept until the next
  // fold, and a pass keeps at least kKeptBins, so that the later, larger requests are prefixes of it.
  constexpr std::size_t kKeptBins = 256;
  std::lock_guard lock(best_.mutex);
  if (best_.asked >= k)
    return {best_.bins.begin(), best_.bins.begin() + static_cast<std::ptrdiff_t>(std::min(k, best_.bins.size()))};
  std::size_t in_band_bins = 0;
  std::vector<BinOffset> best = best_of(
      band_, std::max(k, kKeptBins), [&](std::uint64_t off) { return in_band(off); }, &in_band_bins);
  // Every bin outside the band lies below every bin in it: the band holds the top k unless it has fewer than k
  // bins. A sharp belief asked past its band (an estimate's next modes) takes the whole table, in place.
  std::size_t keep = std::max(k, std::min(kKeptBins, in_band_bins));
  if (in_band_bins < k && in_band_bins < offset_.size()) {
    best = best_past_band(k);
    keep = k;
  }
  best.resize(std::min(keep, best.size()));
  best_.bins = best;
  best_.asked = keep;
  best.resize(std::min(k, best.size()));
  return best;
}

void Belief::drop_upper() const {
  upper_floor_ = 0;
  upper_made_size_ = 0;
  upper_.clear_keeping_capacity();  // as the other tables: a reset keeps the allocation for the next session
}

std::vector<BinOffset> Belief::best_past_band(std::size_t k) const {
  // A kept upper set answers while it holds k bins: every bin outside it lies below its floor, below them all.
  constexpr std::size_t kGrowth = 8;
  if (upper_floor_ != 0 && upper_.size() > kGrowth * upper_made_size_) drop_upper();
  std::size_t passed = 0;
  if (upper_floor_ != 0 && upper_.size() >= k) {
    BeliefTable current(upper_.size());
    upper_.for_each([&](std::uint64_t key, std::uint64_t) { current.set(key, offset_.get(key)); });
    return best_of(
        current, k, [](std::uint64_t) { return true; }, &passed);
  }
  // A pass over the table for 4k bins: those above the 4k-th best's offset become the upper set (equal offsets at
  // the edge stay out, so that every bin outside lies strictly below the floor).
  const std::size_t wide = 4 * k;
  std::vector<BinOffset> best = best_of(
      offset_, wide, [](std::uint64_t) { return true; }, &passed);
  drop_upper();
  if (best.size() == wide && best.back().offset + 1 > best.back().offset) {
    upper_floor_ = best.back().offset + 1;
    for (const BinOffset& b : best)
      if (b.offset >= upper_floor_) upper_.set(b.key, 0);
    upper_made_size_ = std::max<std::size_t>(upper_.size(), 1);
  }
  best.resize(std::min(k, best.size()));
  return best;
}

std::vector<std::uint64_t> Belief::offsets(std::span<const std::uint64_t> keys) const {
  std::vector<std::uint64_t> out;
  out.reserve(keys.size());
  // Home slots loaded ahead, as add() does: a lookup's probe loop branches on its miss too.
  for_each_loaded(
      offset_, keys, [](std::uint64_t k) { return k; }, [&](std::uint64_t k) { out.push_back(offset_.get(k)); });
  return out;
}

std::vector<BinOffset> Belief::table() const {
  std::vector<std::uint64_t> keys, values;
  offset_.sorted(&keys, &values);
  std::vector<BinOffset> out(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) out[i] = {keys[i], values[i]};
  return out;
}

}  // namespace sva
