// The CPU reference vote backend: for every observed pair, every map pair it
// matches (under any of its keys, sva_match_likelihood.h) is aligned once
// (Sec 4.1, 4.3) and scatters the Gaussian in beta into pose bins, with the
// shared math of sva_vote_math.h. Pairs run in parallel on the worker pool;
// each pair's sums are integers, so the result does not depend on the thread
// count, and the fold's integer offsets do not depend on the order of pairs.
#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

#include "backends/cpu/align_lanes.hpp"
#include "backends/cpu/belief.hpp"
#include "backends/cpu/bin_accumulator.hpp"
#include "backends/cpu/hot_path.hpp"
#include "backends/cpu/key_ranges.hpp"
#include "backends/cpu/sample_votes.hpp"
#include "backends/vote_backend.hpp"
#include "votes/vote_math.hpp"

namespace sva {

namespace {

using vote_math::SvaPatch;
using vote_math::vec3;
using Clock = std::chrono::steady_clock;

SvaPatch sva_patch(const ObservedPatch& o) {
  SvaPatch p;
  p.p = vec3(o.position[0], o.position[1], o.position[2]);
  p.n = vec3(o.normal[0], o.normal[1], o.normal[2]);
  p.conf = o.norm_conf;
  return p;
}

using cpu::KeyRange;

class CpuVoteBackend final : public VoteBackend {
 public:
  CpuVoteBackend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings)
      : map_(map), grid_(space.grid()), objects_(space.objects()), settings_(settings) {
    const auto& r = map.readings;
    patches_.resize(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
      patches_[i].p = vec3(r.px[i], r.py[i], r.pz[i]);
      patches_[i].n = vec3(r.nx[i], r.ny[i], r.nz[i]);
      patches_[i].conf = r.norm_conf[i];
    }
  }

  const char* name() const override { return "cpu"; }

  std::vector<PairVotes> vote(const VoteBatch& batch) override {
    const auto start = Clock::now();
    std::vector<PairVotes> out(batch.pairs.size());
    util::parallel_for(
        batch.pairs.size(),
        [&](std::size_t i) {
          BinAccumulator& acc = pair_accumulator();
          vote_pair(batch, batch.pairs[i], key_ranges(batch, batch.pairs[i]), acc, &out[i]);
          out[i].table_probes = acc.probes();
          out[i].bins = acc.size();
          acc.sorted(&out[i].keys, &out[i].mass);
        },
        settings_.threads);
    last_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    last_work_ = work_of(out);
    return out;
  }

  std::unique_ptr<BeliefState> make_belief(const PoseSpace& space, double eps) override {
    return std::make_unique<Belief>(space, eps, settings_.threads);
  }

  // Pairs vote and compute their fold terms in parallel on the worker pool, a pair far larger than a worker's share cut
  // into pieces (vote_and_fold_pieces). One session's pairs then add their terms shard by shard, every shard on its own
  // worker (Belief::add_all): the additions, 14% of the work at 100 paper3d readings, ran under one lock and bounded
  // the update past 8 threads. A batch of sessions adds each pair under its session's lock as it finishes: its many
  // sessions keep the workers apart, and only the pairs in flight hold terms. Integers either way: the order of pairs
  // does not change the belief.
  std::vector<PairStats> vote_and_fold(const VoteBatch& batch, std::span<BeliefState* const> beliefs) override {
    const auto start = Clock::now();
    const std::vector<Belief*> target = cpu_beliefs(batch, beliefs);
    std::vector<PairStats> out(batch.pairs.size());
    std::vector<std::vector<KeyRange>> ranges(batch.pairs.size());
    util::parallel_for(
        batch.pairs.size(), [&](std::size_t i) { ranges[i] = key_ranges(batch, batch.pairs[i]); }, settings_.threads);
    const bool one_session =
        std::all_of(target.begin(), target.end(), [&](const Belief* b) { return b == target.front(); });
    if (!target.empty()) vote_and_fold_pieces(batch, ranges, target, one_session ? 0 : beliefs.size(), out);
    last_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    last_work_ = work_of(out);
    return out;
  }

  BackendStats statistics() const override {
    BackendStats s;
    s.backend = name();
    const unsigned threads = settings_.threads ? settings_.threads : util::default_threads();
    s.device = "CPU reference (" + std::to_string(threads) + " threads)";
    s.last_host_ms = last_ms_;
    s.last_work = last_work_;
    return s;
  }

 private:
  // The worker thread's accumulator for one pair's votes, emptied: a pair at 100 paper3d readings touches tens of
  // thousands of bins, and a fresh table per pair cost its growth, a large allocation (the system's pages, zeroed)
  // and its release every time. Emptying costs the table's size, so a table far larger than the last pair needed
  // (a session of 100 readings, then a new one's first readings) is made again at that pair's size.
  static BinAccumulator& pair_accumulator() {
    thread_local BinAccumulator acc(4096);
    const std::size_t used = std::max<std::size_t>(acc.size(), 4096);
    if (acc.capacity() > 8 * used)
      acc = BinAccumulator(used);
    else
      acc.clear_keeping_capacity();
    return acc;
  }

  // The CPU belief of each pair's session.
  static std::vector<Belief*> cpu_beliefs(const VoteBatch& batch, std::span<BeliefState* const> beliefs) {
    std::vector<Belief*> target(batch.pairs.size());
    for (std::size_t i = 0; i < batch.pairs.size(); ++i) {
      const std::uint32_t s = batch.pairs[i].session;
      if (s >= beliefs.size()) throw Error("cpu backend: pair of session " + std::to_string(s) + " has no belief");
      target[i] = dynamic_cast<Belief*>(beliefs[s]);
      if (!target[i])
        throw Error("cpu backend: session " + std::to_string(s) + " has a belief made by another backend");
    }
    return target;
  }

  // A pair's votes, or a piece's of a pair cut into pieces (split_pairs).
  struct Piece {
    std::size_t pair, part;        // part: its place among the pair's pieces
    std::vector<KeyRange> ranges;  // empty for a whole pair (its own ranges)
    std::uint64_t entries;
  };

  // The pairs' votes and terms on the workers, largest first from one counter (the last to finish is a small one, so no
  // worker waits long for another). A pair far larger than a worker's share is cut into pieces that vote on several
  // workers (split_pairs), and the last of its pieces to finish joins their votes into the pair's terms, shard by shard
  // on every worker (Belief::terms): in one session the largest pair was a fifth of the update's work at 10 paper3d
  // readings and a ninth at 30, and in a batch of 64 sessions at 10 readings a pair of 30-75 ms bounded a step of
  // 945 ms of work, on 16 threads. With `sessions` (a batch) each pair's terms are added under its session's lock as
  // they are made; with 0 (one session) every pair's are added at the end, shard by shard (Belief::add_all). Integer
  // sums: the same terms, and the same belief in any order.
  void vote_and_fold_pieces(const VoteBatch& batch, const std::vector<std::vector<KeyRange>>& ranges,
                            const std::vector<Belief*>& target, std::size_t sessions,
                            std::vector<PairStats>& out) const {
    const std::vector<Piece> pieces = split_pairs(ranges);
    std::vector<BeliefTerms> terms(sessions ? 0 : batch.pairs.size());  // one session's, added at the end
    std::vector<std::mutex> locks(sessions);
    std::vector<std::vector<ShardedVotes>> parts(batch.pairs.size());  // of each cut pair, by part
    std::vector<std::vector<PairStats>> part_stats(batch.pairs.size());
    for (const Piece& piece : pieces)
      if (!piece.ranges.empty()) {
        parts[piece.pair].resize(std::max(parts[piece.pair].size(), piece.part + 1));
        part_stats[piece.pair].resize(parts[piece.pair].size());
      }
    std::vector<std::atomic<std::size_t>> left(batch.pairs.size());  // parts of the pair still voting
    for (std::size_t i = 0; i < left.size(); ++i) left[i].store(parts[i].size(), std::memory_order_relaxed);
    // Pair i's terms, complete: a batch's into its session's belief now.
    const auto made = [&](std::size_t i, const BeliefTerms& t) {
      if (!sessions) return;
      Belief& belief = *target[i];
      std::lock_guard guard(locks[batch.pairs[i].session]);
      const std::uint64_t probes = belief.table_probes();
      out[i].folded = belief.add(t, batch.pairs[i].fold_count);
      out[i].belief_probes = belief.table_probes() - probes;
    };
    util::parallel_deal(
        pieces.size(),
        [&](std::size_t k) {
          const Piece& piece = pieces[k];
          const std::size_t i = piece.pair;
          if (piece.entries == 0) return;    // no match: no votes, no terms (and no table to empty)
          thread_local BeliefTerms scratch;  // a batch's pair's terms, reused (see Belief::terms)
          BeliefTerms& t = sessions ? scratch : terms[i];
          BinAccumulator& acc = pair_accumulator();
          if (piece.ranges.empty()) {  // a whole pair
            vote_pair(batch, batch.pairs[i], ranges[i], acc, &out[i]);
            out[i].table_probes = acc.probes();
            target[i]->terms(acc, &t);
            out[i].bins = t.size();
            return made(i, t);
          }
          PairStats& stats = part_stats[i][piece.part];
          vote_pair(batch, batch.pairs[i], piece.ranges, acc, &stats);
          stats.table_probes = acc.probes();
          ShardedVotes::of(acc, &parts[i][piece.part]);
          if (left[i].fetch_sub(1, std::memory_order_acq_rel) != 1) return;
          join_parts(parts[i], part_stats[i], *target[i], &t, &out[i]);
          made(i, t);
        },
        settings_.threads);
    if (sessions) return;
    std::vector<std::uint32_t> counts(batch.pairs.size());
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = batch.pairs[i].fold_count;
    std::vector<std::uint8_t> folded;
    std::vector<std::uint64_t> probes;
    target.front()->add_all(terms, counts, settings_.threads, &folded, &probes);
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i].folded = folded[i] != 0;
      out[i].belief_probes = probes[i];
    }
  }

  // The update's pairs as work items, the most map entries first: a pair of more than half a worker's fair share
  // (its part of all the pairs' entries, of every session of a batch) is cut into pieces of about that half
  // (key_ranges.hpp, split_by_first_reading), so that no item is much longer than half a share. On 2 workers only a
  // pair of more than a quarter of the entries is cut.
  std::vector<Piece> split_pairs(const std::vector<std::vector<KeyRange>>& ranges) const {
    const std::uint64_t workers = settings_.threads ? settings_.threads : util::default_threads();
    std::vector<std::uint64_t> entries(ranges.size());
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < ranges.size(); ++i) total += entries[i] = cpu::map_entries(ranges[i]);
    const std::uint64_t half_share = std::max<std::uint64_t>(total / (2 * workers), 1);
    std::vector<Piece> pieces;
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const std::uint64_t cut = workers > 1 ? (entries[i] + half_share - 1) / half_share : 1;
      std::vector<std::vector<KeyRange>> split;
      if (cut > 1) split = cpu::split_by_first_reading(map_, ranges[i], cut);
      if (split.size() <= 1) {
        pieces.push_back({i, 0, {}, entries[i]});
        continue;
      }
      for (std::size_t j = 0; j < split.size(); ++j) {
        const std::uint64_t n = cpu::map_entries(split[j]);
        pieces.push_back({i, j, std::move(split[j]), n});
      }
    }
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const Piece& a, const Piece& b) { return a.entries > b.entries; });
    return pieces;
  }

  // A cut pair's parts joined into its terms (each bin's votes summed over the parts: the whole pair's), its counts
  // summed.
  void join_parts(const std::vector<ShardedVotes>& parts, const std::vector<PairStats>& stats, const Belief& belief,
                  BeliefTerms* terms, PairStats* out) const {
    for (const PairStats& p : stats) {
      out->entries += p.entries;
      out->matches += p.matches;
      out->votes += p.votes;
      out->votes_outside += p.votes_outside;
      out->votes_zero += p.votes_zero;
      out->table_probes += p.table_probes;
    }
    std::uint64_t probes = 0;
    belief.terms(parts, settings_.threads, terms, &probes);
    out->table_probes += probes;
    out->bins = terms->size();
  }

  // The ranges of the pair's keys that the map holds, in the pair's key order.
  std::vector<KeyRange> key_ranges(const VoteBatch& batch, const PairQuery& q) const {
    std::vector<KeyRange> ranges;
    for (std::uint32_t k = q.key_begin; k < q.key_end; ++k) {
      const PairKeyWeight kw = batch.keys[k];
      const auto it = std::lower_bound(map_.keys.begin(), map_.keys.end(), kw.key);
      if (it == map_.keys.end() || *it != kw.key) continue;
      const std::size_t slot = static_cast<std::size_t>(it - map_.keys.begin());
      ranges.push_back({map_.offsets[slot], map_.offsets[slot + 1], kw.weight, kw.reversed != 0});
    }
    return ranges;
  }

  void vote_pair(const VoteBatch& batch, const PairQuery& q, const std::vector<KeyRange>& ranges, BinAccumulator& acc,
                 PairStats* out) const {
    const SvaPatch a1 = sva_patch(q.a), b1 = sva_patch(q.b);
    const std::uint8_t* active =
        batch.object_active.empty() ? nullptr : batch.object_active.data() + std::size_t{q.session} * objects_;
    std::uint32_t seen = 0;
    out->entries += cpu::map_entries(ranges);
    // Matches are aligned a block at a time (align_lanes.hpp), then each votes.
    const cpu::ObservedLanes observed(a1, b1);
    cpu::MatchLanes block;
    const auto vote_block = [&] {
      vote_matches(observed, block, acc, out);
      block.n = 0;
    };
    cpu::for_each_match(map_, ranges,
                        [&](std::uint32_t entry, std::uint32_t ra, std::uint32_t rb, std::uint64_t units) {
                          if ((++seen & 1023u) == 0) util::throw_if_interrupted();
                          const std::uint32_t object = map_.readings.object[map_.entry_a[entry]];
                          if (active && !active[object]) return;
                          const float likelihood = vote_math::sva_likelihood_of_units(units);
                          if (!(likelihood > 0.0f) || likelihood < settings_.likelihood_cutoff) return;
                          block.ra[block.n] = ra;
                          block.rb[block.n] = rb;
                          block.object[block.n] = object;
                          block.likelihood[block.n] = likelihood;
                          if (++block.n == cpu::MatchLanes::kLanes) vote_block();
                        });
    if (block.n > 0) vote_block();
  }

  // Aligns and plans a block of matches (lane by lane) and scatters each one's beta samples (computed lane by lane,
  // sample_votes.hpp: sva_vote's bits).
  SVA_HOT_PATH void vote_matches(const cpu::ObservedLanes& observed, const cpu::MatchLanes& block, BinAccumulator& acc,
                                 PairStats* out) const {
    vote_math::SvaAlignment al[cpu::MatchLanes::kLanes];
    vote_math::SvaBetaPlan plan[cpu::MatchLanes::kLanes];
    cpu::align_lanes(observed, patches_, grid_, block, al, plan);
    for (int m = 0; m < block.n; ++m) {
      if (plan[m].n == 0) continue;
      ++out->matches;
      cpu::SampleVotes votes;
      cpu::sample_votes(al[m], plan[m], grid_, block.object[m], block.likelihood[m], &votes);
      add_votes(votes, acc, out);
    }
  }

  // Neighbouring samples often share a bin (they are half a bin apart): a run of one key goes into the table as one
  // sum (integers: same result).
  static void add_votes(const cpu::SampleVotes& votes, BinAccumulator& acc, PairStats* out) {
    std::uint64_t run_key = 0;
    std::int64_t run_mass = 0;
    for (int s = 0; s < votes.n; ++s) {
      if (!votes.inside[s]) {
        ++out->votes_outside;
        continue;
      }
      ++out->votes;
      if (votes.mass[s] <= 0) {
        ++out->votes_zero;
        continue;
      }
      if (run_mass > 0 && votes.key[s] != run_key) {
        acc.add(run_key, run_mass);
        run_mass = 0;
      }
      run_key = votes.key[s];
      run_mass += votes.mass[s];
    }
    if (run_mass > 0) acc.add(run_key, run_mass);
  }

  const PairMap& map_;
  vote_math::SvaPoseGrid grid_;
  std::uint32_t objects_;
  VoteSettings settings_;
  std::vector<SvaPatch> patches_;
  double last_ms_ = 0.0;             // host time of the last vote or vote_and_fold
  BatchRecognizer::Work last_work_;  // and what it did
};

}  // namespace

std::unique_ptr<VoteBackend> make_cpu_vote_backend(const PairMap& map, const PoseSpace& space,
                                                   const VoteSettings& settings) {
  return std::make_unique<CpuVoteBackend>(map, space, settings);
}

}  // namespace sva
