#include "backends/cpu/belief.hpp"

#include <sva/base/parallel.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <limits>

#include "backends/cpu/fold_lanes.hpp"
#include "backends/vote_backend.hpp"
#include "belief/belief_math.hpp"

namespace sva {

namespace {
// A shard's first table: small, so that a batch of thousands of sessions starts small (its tables grow as it folds).
constexpr std::size_t kShardStart = 64;
}  // namespace

BeliefTerms BeliefTerms::grouped(std::span<const BinOffset> terms) {
  BeliefTerms out;
  for (const BinOffset& t : terms) ++out.begin[belief_shard_of(t.key) + 1];
  for (std::size_t s = 0; s < kBeliefShards; ++s) out.begin[s + 1] += out.begin[s];
  std::array<std::uint32_t, kBeliefShards> next;
  std::copy(out.begin.begin(), out.begin.end() - 1, next.begin());
  out.terms.resize(terms.size());
  for (const BinOffset& t : terms) out.terms[next[belief_shard_of(t.key)]++] = t;
  return out;
}

Belief::Belief(const PoseSpace& space, double eps, unsigned threads)
    : space_(&space), eps_units_(belief_math::eps_units(eps)), threads_(threads) {
  const std::uint32_t mass_bits = belief_math::mass_bits(space.bins_per_object());
  shards_.reserve(kBeliefShards);
  for (std::size_t s = 0; s < kBeliefShards; ++s) shards_.emplace_back(space.objects(), mass_bits, kShardStart);
}

void Belief::reset() {
  forget_best();
  for (BeliefShard& s : shards_) s.reset();
  pairs_ = 0;
}

bool Belief::fold(const PairVotes& votes, std::uint32_t count) {
  assert(votes.keys.size() == votes.mass.size());
  BinAccumulator acc(votes.keys.size());
  for (std::size_t i = 0; i < votes.keys.size(); ++i) acc.add(votes.keys[i], votes.mass[i]);
  return add(terms(acc), count);
}

BeliefTerms Belief::terms(const BinAccumulator& votes) const {
  BeliefTerms out;
  terms(votes, &out);
  return out;
}

void Belief::terms(const BinAccumulator& votes, BeliefTerms* out) const {
  // The worker thread's scratch, kept between pairs: a pair's bins run to tens of thousands, and buffers that size
  // allocated and freed per pair went back to the system and came back as fresh (zeroed, faulted-in) pages.
  thread_local ShardedVotes grouped;
  thread_local std::vector<std::uint64_t> units;
  ShardedVotes::of(votes, &grouped);  // the bins with votes, by shard, each shard in the pair table's slot order
  out->terms.clear();
  out->begin = grouped.begin;
  const std::size_t n = grouped.key.size();
  if (n == 0) return;
  if (units.size() < n) units.resize(n);  // sized up only, as the scratch is
  // Masses are positive: int64 and uint64 share the bits. total < 2^63: votes are clamped (SVA_FIXED_MAX_VOTE_UNITS).
  const auto* mass = reinterpret_cast<const std::uint64_t*>(grouped.mass.data());
  cpu::fold_units(mass, n, grouped.total, eps_units_, belief_math::sva_floor_log(grouped.total, eps_units_),
                  units.data());
  out->terms.resize(n);
  for (std::size_t i = 0; i < n; ++i) out->terms[i] = {grouped.key[i], units[i]};
}

void ShardedVotes::of(const BinAccumulator& votes, ShardedVotes* out) {
  thread_local std::vector<std::uint64_t> key;  // scratch, as Belief::terms's, sized up only
  thread_local std::vector<std::int64_t> mass;
  thread_local std::vector<std::uint8_t> shard;
  if (key.size() < votes.size() + 1) {
    key.resize(votes.size() + 1);
    mass.resize(votes.size() + 1);
    shard.resize(votes.size() + 1);
  }
  const std::size_t n = votes.copy_positive(key.data(), mass.data());
  out->begin.fill(0);
  out->total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    shard[i] = static_cast<std::uint8_t>(belief_shard_of(key[i]));
    ++out->begin[shard[i] + 1];
    out->total += static_cast<std::uint64_t>(mass[i]);
  }
  for (std::size_t s = 0; s < kBeliefShards; ++s) out->begin[s + 1] += out->begin[s];
  std::array<std::uint32_t, kBeliefShards> next;
  std::copy(out->begin.begin(), out->begin.end() - 1, next.begin());
  out->key.resize(n);
  out->mass.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t at = next[shard[i]]++;
    out->key[at] = key[i];
    out->mass[at] = mass[i];
  }
}

namespace {

// One shard's bins of a pair's parts, summed per bin: a table sized for them all beforehand (never grown, so filling
// it in the parts' slot order costs no sweep, bin_accumulator.hpp), its homes above the shard's bits, which its keys
// share. The worker's table, kept between joins where it is the size this one needs: emptying it and reading it out
// cost its size, and larger ones kept from larger joins took 14% of an update's samples on 16 threads (notebook,
// recognition-2026-11.md, "an eighth session").
using ShardJoin = BinTable<std::int64_t, HomeBits::low, kBeliefShardBits>;
ShardJoin& shard_join(std::size_t expected) {
  thread_local ShardJoin table(1024);
  if (table.capacity() != ShardJoin::capacity_for(expected))
    table = ShardJoin(expected);
  else
    table.clear_keeping_capacity();
  return table;
}

}  // namespace

void Belief::terms(std::span<const ShardedVotes> parts, unsigned threads, BeliefTerms* out,
                   std::uint64_t* probes) const {
  out->terms.clear();
  out->begin.fill(0);
  *probes = 0;
  std::uint64_t total = 0;  // < 2^63 as a whole pair's
  for (const ShardedVotes& p : parts) total += p.total;
  if (total == 0) return;
  const std::uint64_t floor_log = belief_math::sva_floor_log(total, eps_units_);
  std::array<std::vector<BinOffset>, kBeliefShards> joined;
  std::array<std::uint64_t, kBeliefShards> shard_probes{};
  util::parallel_for(
      kBeliefShards,
      [&](std::size_t s) {
        std::size_t expected = 0;
        for (const ShardedVotes& p : parts) expected += p.begin[s + 1] - p.begin[s];
        ShardJoin& table = shard_join(expected);
        for (const ShardedVotes& p : parts)
          for (std::uint32_t j = p.begin[s]; j < p.begin[s + 1]; ++j) table.add(p.key[j], p.mass[j]);
        shard_probes[s] = table.probes();
        thread_local std::vector<std::uint64_t> key, mass, units;
        if (key.size() < table.size() + 1) {
          key.resize(table.size() + 1);
          mass.resize(table.size() + 1);
          units.resize(table.size() + 1);
        }
        const std::size_t n = table.copy_positive(key.data(), reinterpret_cast<std::int64_t*>(mass.data()));
        cpu::fold_units(mass.data(), n, total, eps_units_, floor_log, units.data());
        joined[s].resize(n);
        for (std::size_t i = 0; i < n; ++i) joined[s][i] = {key[i], units[i]};
      },
      threads);
  for (std::size_t s = 0; s < kBeliefShards; ++s) {
    out->begin[s + 1] = out->begin[s] + static_cast<std::uint32_t>(joined[s].size());
    out->terms.insert(out->terms.end(), joined[s].begin(), joined[s].end());
    *probes += shard_probes[s];
  }
}

bool Belief::add(const BeliefTerms& terms, std::uint32_t count) {
  if (terms.empty() || count == 0) return false;
  forget_best();
  for (std::size_t s = 0; s < kBeliefShards; ++s) shards_[s].add(terms.shard(s), count);
  pairs_ += count;
  return true;
}

void Belief::add_all(std::span<const BeliefTerms> terms, std::span<const std::uint32_t> counts, unsigned threads,
                     std::vector<std::uint8_t>* folded, std::vector<std::uint64_t>* probes) {
  if (counts.size() != terms.size())
    throw Error("belief: " + std::to_string(terms.size()) + " pairs' terms but " + std::to_string(counts.size()) +
                " counts");
  forget_best();
  // Each shard's additions per pair, so that a pair's probes are its own whichever worker made them.
  std::vector<std::uint64_t> shard_probes(terms.size() * kBeliefShards, 0);
  util::parallel_for(
      kBeliefShards,
      [&](std::size_t s) {
        for (std::size_t i = 0; i < terms.size(); ++i) {
          if (terms[i].empty() || counts[i] == 0) continue;
          const std::uint64_t before = shards_[s].probes();
          shards_[s].add(terms[i].shard(s), counts[i]);
          shard_probes[i * kBeliefShards + s] = shards_[s].probes() - before;
        }
      },
      threads);
  folded->assign(terms.size(), 0);
  probes->assign(terms.size(), 0);
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (terms[i].empty() || counts[i] == 0) continue;
    (*folded)[i] = 1;
    pairs_ += counts[i];
    for (std::size_t s = 0; s < kBeliefShards; ++s) (*probes)[i] += shard_probes[i * kBeliefShards + s];
  }
}

namespace {
// A figure summed over the shards (what the belief as a whole reports).
template <class Of>
std::uint64_t over_shards(const std::vector<BeliefShard>& shards, Of of) {
  std::uint64_t n = 0;
  for (const BeliefShard& s : shards) n += of(s);
  return n;
}
}  // namespace

std::size_t Belief::table_allocations() const {
  return over_shards(shards_, [](const BeliefShard& s) { return s.allocations(); });
}
std::size_t Belief::touched() const {
  return over_shards(shards_, [](const BeliefShard& s) { return s.size(); });
}
std::size_t Belief::table_bytes() const {
  return over_shards(shards_, [](const BeliefShard& s) { return s.bytes(); });
}
std::uint64_t Belief::table_probes() const {
  return over_shards(shards_, [](const BeliefShard& s) { return s.probes(); });
}

std::size_t Belief::forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) {
  forget_best();
  std::array<std::vector<std::uint64_t>, kBeliefShards> kept;  // `keep` by shard, each still sorted
  for (const std::uint64_t key : keep) kept[belief_shard_of(key)].push_back(key);
  std::size_t forgotten = 0;
  for (std::size_t s = 0; s < kBeliefShards; ++s) forgotten += shards_[s].forget_below(below, kept[s]);
  return forgotten;
}

void Belief::forget_best() {
  std::lock_guard lock(best_.mutex);
  best_.bins.clear();
  best_.asked = 0;
}

BeliefSummary Belief::summarise() const {
  BeliefSummary s;
  const std::uint32_t objects = space_->objects();
  s.touched.assign(objects, 0);
  s.best_offset.assign(objects, 0);
  s.best_key.assign(objects, 0);
  s.touched_mass.assign(objects, 0);
  for (const BeliefShard& shard : shards_) s.max_offset = std::max(s.max_offset, shard.max_offset());
  // Each shard's band mass on its own worker (an exp2 per bin in the band), summed in integers afterwards.
  std::vector<std::vector<std::uint64_t>> mass(kBeliefShards, std::vector<std::uint64_t>(objects, 0));
  util::parallel_for(
      kBeliefShards, [&](std::size_t i) { shards_[i].add_band_mass(s.max_offset, &mass[i]); }, threads_);
  for (const std::vector<std::uint64_t>& m : mass)
    for (std::uint32_t o = 0; o < objects; ++o) s.touched_mass[o] += m[o];
  for (const BeliefShard& shard : shards_) {
    for (std::uint32_t o = 0; o < objects; ++o) {
      const std::uint64_t n = shard.touched_per_object()[o];
      if (n == 0) continue;
      const BinOffset mine{shard.best_key()[o], shard.best_offset()[o]};
      if (s.touched[o] == 0 || better_bin(mine, {s.best_key[o], s.best_offset[o]})) {
        s.best_offset[o] = mine.offset;
        s.best_key[o] = mine.key;
      }
      s.touched[o] += n;
    }
  }
  return s;
}

namespace {

// Loads the home slots of keys in their shards' tables (for_each_loaded's table, for a sharded belief).
struct ShardHomes {
  const std::vector<BeliefShard>* shards;
  template <class It, class KeyOf>
  void load_homes(It first, It last, KeyOf key_of) const {
    std::uint64_t seen = 0;
    for (; first != last; ++first) {
      const std::uint64_t k = key_of(*first);
      seen ^= (*shards)[belief_shard_of(k)].home_key(k);
    }
    sink ^= seen;  // kept, so that the loads are made
  }
  mutable std::uint64_t sink = 0;
};

// The merged lists of every shard's exact top n_s bins, best first, cut where a bin might be missing: a merged bin is
// in its exact place while it is no worse than the last bin of every shard that gave fewer than all of its bins
// (whatever such a shard left out lies below its last).
std::vector<BinOffset> merge_tops(const std::vector<std::vector<BinOffset>>& tops,
                                  const std::vector<BeliefShard>& shards) {
  std::vector<BinOffset> all;
  const BinOffset* edge = nullptr;
  for (std::size_t s = 0; s < tops.size(); ++s) {
    if (!tops[s].empty() && tops[s].size() < shards[s].size() && (!edge || better_bin(tops[s].back(), *edge)))
      edge = &tops[s].back();
    all.insert(all.end(), tops[s].begin(), tops[s].end());
  }
  std::sort(all.begin(), all.end(), better_bin);
  if (edge)
    all.erase(std::partition_point(all.begin(), all.end(), [&](const BinOffset& b) { return !better_bin(*edge, b); }),
              all.end());
  return all;
}

}  // namespace

std::vector<BinOffset> Belief::best_bins(std::size_t k) const {
  // One estimate asks for the best bins several times (the estimate's top bins, each object's modes, the
  // hypotheses, the surface check's three objects), each a pass over the bands: the answer is kept until the next
  // fold, and each shard gives at least kKeptPerShard bins of its band, so that the later, larger requests are
  // prefixes of it.
  constexpr std::size_t kKeptPerShard = 16;
  std::lock_guard lock(best_.mutex);
  if (best_.asked >= k)
    return {best_.bins.begin(), best_.bins.begin() + static_cast<std::ptrdiff_t>(std::min(k, best_.bins.size()))};
  // First from the bands alone; a shard that the merge needs past its band (a sharp belief, an estimate's next
  // modes) then gives its top k, from a pass over its table.
  // Each shard's pass on its own worker (a shard's kept upper set is its own).
  std::vector<std::vector<BinOffset>> tops(kBeliefShards);
  util::parallel_for(
      kBeliefShards, [&](std::size_t s) { tops[s] = shards_[s].band_top(std::max(k, kKeptPerShard)); }, threads_);
  std::vector<BinOffset> best = merge_tops(tops, shards_);
  // Each shard holds about k / 32 of the top k (bins fall in shards by their hash): asked for twice that, a shard
  // past its band makes an upper set of its own share, not of all k; asked again for twice as many while the merge
  // is short. Once a shard gives k bins (or all), the merge holds k: the loop ends.
  const std::size_t bins = touched();
  for (std::size_t want = 2 * ((k + kBeliefShards - 1) / kBeliefShards) + 8; best.size() < std::min(k, bins);
       want *= 2) {
    util::parallel_for(
        kBeliefShards,
        [&](std::size_t s) {
          if (tops[s].size() < std::min(want, k) && tops[s].size() < shards_[s].size())
            tops[s] = shards_[s].top(std::min(want, k));
        },
        threads_);
    best = merge_tops(tops, shards_);
  }
  best_.asked = best.size() < bins ? best.size() : std::numeric_limits<std::size_t>::max();
  best_.bins = best;
  best.resize(std::min(k, best.size()));
  return best;
}

std::vector<std::uint64_t> Belief::offsets(std::span<const std::uint64_t> keys) const {
  std::vector<std::uint64_t> out(keys.size());
  // Home slots loaded ahead, as a shard's additions do: a lookup's probe loop branches on its miss too. Chunks of the
  // keys on the workers: an estimate's neighbourhoods ask about 10,000 lookups, each a wait on memory, which were a
  // third of one session's critical path (notebook recognition-2026-11.md, "a seventh session").
  // A chunk is a worker's share, at least 256 lookups (so that a task is worth its scheduling) and at most 2,048:
  // 2,048 a chunk left one session's 9,477 lookups at 30 paper3d readings in 5 chunks, a sixth of its estimate's
  // critical path on 16 workers.
  const ShardHomes homes{&shards_};
  const std::size_t workers = threads_ ? threads_ : util::default_threads();
  const std::size_t chunk = std::clamp<std::size_t>((keys.size() + workers - 1) / workers, 256, 2048);
  const std::size_t chunks = (keys.size() + chunk - 1) / chunk;
  util::parallel_for(
      chunks,
      [&](std::size_t c) {
        const std::size_t begin = c * chunk, n = std::min(chunk, keys.size() - begin);
        std::size_t i = begin;
        for_each_loaded(
            homes, keys.subspan(begin, n), [](std::uint64_t k) { return k; },
            [&](std::uint64_t k) { out[i++] = offset(k); });
      },
      threads_);
  return out;
}

std::vector<BinOffset> Belief::table() const {
  std::vector<BinOffset> out;
  out.reserve(touched());
  for (const BeliefShard& s : shards_)
    s.for_each([&](std::uint64_t key, std::uint64_t off) { out.push_back({key, off}); });
  std::sort(out.begin(), out.end(), [](const BinOffset& a, const BinOffset& b) { return a.key < b.key; });
  return out;
}

}  // namespace sva
