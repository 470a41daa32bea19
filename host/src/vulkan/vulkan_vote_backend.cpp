#include "vulkan/vulkan_vote_backend.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "core/hash.hpp"
#include "spv/belief_fold.h"
#include "spv/belief_lookup.h"
#include "spv/belief_reduce.h"
#include "spv/belief_rehash.h"
#include "spv/expand_pair_keys.h"
#include "spv/match_votes.h"
#include "spv/scan_matches.h"
#include "util/interrupt.hpp"
#include "vulkan/context.hpp"
#include "vulkan/gpu_belief.hpp"
#include "vulkan/gpu_layout.hpp"
#include "vulkan/linear_bins.hpp"

namespace sva {

namespace {
using Clock = std::chrono::steady_clock;
using gpu::ensure;
using gpu::push_bytes;
}  // namespace

class VulkanVoteBackend final : public VoteBackend {
 public:
  VulkanVoteBackend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings, const VulkanBackendOptions& options)
      : map_(map), space_(space), settings_(settings), ctx_(context_options(options)), bins_(space),
        expand_(ctx_.create_pipeline(sva_spv_expand_pair_keys, 4, sizeof(gpu::SvaExpandParams))),
        scan_(ctx_.create_pipeline(sva_spv_scan_matches, 3, sizeof(gpu::SvaScanParams))),
        pipeline_(ctx_.create_pipeline(sva_spv_match_votes, 15, sizeof(gpu::SvaMatchParams))),
        fold_(ctx_.create_pipeline(sva_spv_belief_fold, 6, sizeof(gpu::SvaFoldParams))),
        beliefs_{&ctx_,
                 &space,
                 LinearBins(space),
                 ctx_.create_pipeline(sva_spv_belief_rehash, 1, sizeof(gpu::SvaRehashParams)),
                 ctx_.create_pipeline(sva_spv_belief_reduce, 2, sizeof(gpu::SvaReduceParams)),
                 ctx_.create_pipeline(sva_spv_belief_lookup, 1, sizeof(gpu::SvaLookupParams)),
                 std::max<std::size_t>(options.initial_belief_slots, 64),
                 0.0} {
    stats_.device = ctx_.info().name + " (" + ctx_.info().type + ")";
    const std::size_t range_entries = ctx_.info().max_storage_buffer_range / sizeof(std::uint32_t);
    chunk_ = options.max_chunk_entries ? std::min(options.max_chunk_entries, range_entries) : range_entries;
    slots_ = std::bit_ceil(std::max<std::size_t>(options.initial_table_slots, 1024));
    const auto& r = map.readings;
    if (r.size() * sizeof(gpu::SvaGpuReading) > ctx_.info().max_storage_buffer_range)
      throw Error("map has too many readings for one GPU binding (" + std::to_string(r.size()) + ")");
    readings_ = ctx_.create_buffer(r.size() * sizeof(gpu::SvaGpuReading));
    auto* g = readings_.as<gpu::SvaGpuReading>();
    for (std::size_t i = 0; i < r.size(); ++i)
      g[i] = {r.px[i], r.py[i], r.pz[i], r.norm_conf[i], r.nx[i], r.ny[i], r.nz[i], r.object[i]};
    if (map.keys.size() * sizeof(std::uint32_t) >= ctx_.info().max_storage_buffer_range)
      throw Error("map has too many keys for one GPU binding (" + std::to_string(map.keys.size()) + ")");
    map_keys_ = ctx_.create_buffer(map.keys.size() * sizeof(std::uint32_t));
    map_offsets_ = ctx_.create_buffer(map.offsets.size() * sizeof(std::uint32_t));
    if (!map.keys.empty()) std::memcpy(map_keys_.data(), map.keys.data(), map.keys.size() * sizeof(std::uint32_t));
    if (!map.offsets.empty()) std::memcpy(map_offsets_.data(), map.offsets.data(), map.offsets.size() * sizeof(std::uint32_t));
    const std::size_t entries = map.entry_count();
    for (std::size_t begin = 0; begin < entries || begin == 0; begin += chunk_) {
      const std::size_t n = std::min(chunk_, entries - begin);
      Chunk c;
      c.begin = begin;
      c.count = n;
      c.a = ctx_.create_buffer(n * sizeof(std::uint32_t));
      c.b = ctx_.create_buffer(n * sizeof(std::uint32_t));
      c.w = ctx_.create_buffer(n * sizeof(float));
      if (n) {
        std::memcpy(c.a.data(), map.entry_a.data() + begin, n * sizeof(std::uint32_t));
        std::memcpy(c.b.data(), map.entry_b.data() + begin, n * sizeof(std::uint32_t));
        std::memcpy(c.w.data(), map.entry_weight.data() + begin, n * sizeof(float));
      }
      chunks_.push_back(std::move(c));
      if (entries == 0) break;
    }
    stats_.chunks = chunks_.size();
    chunk_table_ = ctx_.create_buffer(chunks_.size() * sizeof(gpu::SvaGpuChunk));
    auto* ct = chunk_table_.as<gpu::SvaGpuChunk>();
    for (std::size_t i = 0; i < chunks_.size(); ++i) {
      const VkDeviceAddress a = chunks_[i].a.device_address(), b = chunks_[i].b.device_address(),
                            w = chunks_[i].w.device_address();
      ct[i] = {gpu::lo(a), gpu::hi(a), gpu::lo(b), gpu::hi(b), gpu::lo(w), gpu::hi(w), 0u, 0u};
    }
  }

  const char* name() const override { return "vulkan"; }
  const VulkanBackendStats& stats() const { return stats_; }


  std::vector<PairVotes> vote(const VoteBatch& batch) override {
    std::vector<PairVotes> out(batch.pairs.size());
    timed([&] {
      vote_pairs(batch, 0, batch.pairs.size(), [&](std::size_t first, std::size_t last) { read_back(first, last, out); });
    });
    return out;
  }

  std::unique_ptr<BeliefState> make_belief(const PoseSpace& space, double eps) override {
    if (&space != &space_) throw Error("vulkan backend: a belief must use the backend's pose space");
    return std::make_unique<GpuBelief>(beliefs_, eps);
  }

  std::vector<PairStats> vote_and_fold(const VoteBatch& batch, std::span<BeliefState* const> beliefs) override {
    std::vector<GpuBelief*> gb;
    for (BeliefState* b : beliefs) {
      auto* g = dynamic_cast<GpuBelief*>(b);
      if (!g) throw Error("vulkan backend: a session's belief was made by another backend");
      gb.push_back(g);
    }
    for (const PairQuery& q : batch.pairs)
      if (q.session >= gb.size()) throw Error("vulkan backend: pair of session " + std::to_string(q.session) + " has no belief");
    std::vector<PairStats> out(batch.pairs.size());
    timed([&] {
      vote_pairs(batch, 0, batch.pairs.size(), [&](std::size_t first, std::size_t last) { fold(batch, first, last, gb, out); });
      for (GpuBelief* g : gb) g->keep_half_empty();
    });
    return out;
  }

 private:
  struct Chunk {
    std::size_t begin = 0, count = 0;
    vk::Buffer a, b, w, offsets, scan;
  };

  template <class Fn>
  void timed(Fn&& fn) {
    const auto t0 = Clock::now();
    kernel_ms_ = 0.0;
    fold_ms_ = 0.0;
    beliefs_.kernel_ms = 0.0;
    fn();
    fold_ms_ += beliefs_.kernel_ms;  // table growth during the fold
    kernel_ms_ += fold_ms_;
    stats_.last_fold_ms = fold_ms_;
    stats_.table_slots = slots_;
    stats_.last_kernel_ms = kernel_ms_;
    stats_.last_host_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() - kernel_ms_;
    stats_.validation_messages = ctx_.validation_messages();
  }

  // Votes of pairs [first, last) of the batch into the vote table, then
  // consume(first, last) while the table holds them. All vote work runs in
  // one submission: expand keys to map ranges, then per map chunk a scan of
  // its matches and the indirect match kernel. A batch too large for one pass
  // (key items, table or 2^32 matches in a chunk) is split in halves.
  using Consumer = std::function<void(std::size_t, std::size_t)>;
  void vote_pairs(const VoteBatch& batch, std::size_t first, std::size_t last, const Consumer& consume) {
    if (first >= last) return;
    const std::size_t P = last - first;
    const std::uint32_t objects = space_.objects();
    std::vector<gpu::SvaGpuKeyItem> items;
    std::vector<std::uint32_t> item_begin(P + 1, 0);
    for (std::size_t q = first; q < last; ++q) {
      item_begin[q - first] = static_cast<std::uint32_t>(items.size());
      for (std::uint32_t k = batch.pairs[q].key_begin; k < batch.pairs[q].key_end; ++k)
        items.push_back({static_cast<std::uint32_t>(q - first), batch.keys[k].key, batch.keys[k].weight, 0u});
    }
    item_begin[P] = static_cast<std::uint32_t>(items.size());  // <= SVA_MAX_KEY_ITEMS (checked below)
    if (items.empty()) {  // no pair looks anything up: no votes
      consume_empty(first, last, consume);
      return;
    }
    if (items.size() > SVA_MAX_KEY_ITEMS && P > 1) {
      split(batch, first, last, consume);
      return;
    }
    if (items.size() > SVA_MAX_KEY_ITEMS) throw Error("one observed pair has more map keys than the GPU backend handles");
    if (P > bins_.max_pairs()) {
      split(batch, first, last, consume);
      return;
    }
    const std::size_t K = items.size();
    ensure(ctx_, pairs_, P * sizeof(gpu::SvaGpuPair));
    auto* gp = pairs_.as<gpu::SvaGpuPair>();
    for (std::size_t q = 0; q < P; ++q) {
      const PairQuery& pq = batch.pairs[first + q];
      gp[q] = {pq.a.position[0], pq.a.position[1], pq.a.position[2], pq.a.norm_conf, pq.a.normal[0], pq.a.normal[1],
               pq.a.normal[2], pq.session, pq.b.position[0], pq.b.position[1], pq.b.position[2], pq.b.norm_conf,
               pq.b.normal[0], pq.b.normal[1], pq.b.normal[2], pq.fold_count, item_begin[q], item_begin[q + 1], 0u, 0u};
    }
    ensure(ctx_, key_items_, K * sizeof(gpu::SvaGpuKeyItem));
    std::memcpy(key_items_.data(), items.data(), K * sizeof(gpu::SvaGpuKeyItem));
    ensure(ctx_, ranges_, K * sizeof(gpu::SvaGpuRange));
    const std::size_t sessions = std::max<std::uint32_t>(batch.sessions, 1);
    ensure(ctx_, active_, sessions * objects * sizeof(std::uint32_t));
    auto* act = active_.as<std::uint32_t>();
    for (std::size_t i = 0; i < sessions * objects; ++i)
      act[i] = batch.object_active.empty() ? 1u : (i < batch.object_active.size() && batch.object_active[i] ? 1u : 0u);
    for (Chunk& ch : chunks_) {
      ensure(ctx_, ch.offsets, (K + 1) * sizeof(std::uint32_t));
      ensure(ctx_, ch.scan, sizeof(gpu::SvaScanResult));
    }
    ensure(ctx_, counters_, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
    ensure(ctx_, status_, sizeof(std::uint32_t));

    const auto grid = space_.grid();
    for (;;) {
      util::throw_if_interrupted();
      if (slots_ > max_slots()) {
        if (P > 1) {
          slots_ = max_slots();  // each half starts from the largest table one binding holds
          split(batch, first, last, consume);
          return;
        }
        throw Error("GPU vote table would exceed one binding (" + std::to_string(slots_) + " slots) for one pair");
      }
      ensure(ctx_, table_keys_, slots_ * sizeof(std::uint64_t));
      ensure(ctx_, table_sums_, slots_ * sizeof(std::int64_t));
      const std::vector<vk::Fill> clear{{&table_keys_, 0xffffffffu, 0, slots_ * sizeof(std::uint64_t)},
                                        {&table_sums_, 0u, 0, slots_ * sizeof(std::int64_t)}};
      std::memset(counters_.data(), 0, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
      *status_.as<std::uint32_t>() = 0;
      std::vector<vk::Dispatch> dispatches;
      gpu::SvaExpandParams ep{static_cast<std::uint32_t>(K), static_cast<std::uint32_t>(map_.keys.size())};
      dispatches.push_back({&expand_, {&key_items_, &map_keys_, &map_offsets_, &ranges_}, push_bytes(ep),
                            static_cast<std::uint32_t>((K + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)});
      for (Chunk& ch : chunks_) {
        if (ch.count == 0) continue;
        gpu::SvaScanParams sp{static_cast<std::uint32_t>(K), static_cast<std::uint32_t>(ch.begin),
                              static_cast<std::uint32_t>(ch.begin + ch.count), ctx_.info().max_workgroup_count_x};
        dispatches.push_back({&scan_, {&ranges_, &ch.offsets, &ch.scan}, push_bytes(sp), 1});
        gpu::SvaMatchParams p{};
        p.key_items = static_cast<std::uint32_t>(K);
        p.chunk_begin = static_cast<std::uint32_t>(ch.begin);
        p.chunk_end = static_cast<std::uint32_t>(ch.begin + ch.count);
        p.capacity = static_cast<std::uint32_t>(slots_);
        p.objects = objects;
        p.grid_kind = static_cast<std::uint32_t>(grid.kind);
        p.translation_bins = grid.translation_bins;
        p.translation_min = grid.translation_min;
        p.translation_width = grid.translation_width;
        p.rotation_bins = grid.rotation_bins;
        p.rotation_width = grid.rotation_width;
        p.likelihood_cutoff = settings_.likelihood_cutoff;
        p.dim_tz = bins_.dim_tz();
        p.dim_rxy = bins_.dim_rxy();
        p.object_shift = bins_.object_shift();
        p.pair_shift = bins_.pair_shift();
        p.chunk_entries = static_cast<std::uint32_t>(chunk_);
        vk::Dispatch d{&pipeline_,
                       {&pairs_, &key_items_, &ranges_, &ch.offsets, &readings_, &ch.a, &ch.b, &ch.w, &active_, &table_keys_,
                        &table_sums_, &counters_, &status_, &ch.scan, &chunk_table_},
                       push_bytes(p), 0};
        d.indirect = &ch.scan;
        dispatches.push_back(std::move(d));
      }
      std::vector<double> ms;
      ctx_.run(dispatches, &ms, clear);
      for (double m : ms) kernel_ms_ += m;
      bool too_many = false;
      for (Chunk& ch : chunks_)
        if (ch.count && ch.scan.as<gpu::SvaScanResult>()->too_many) too_many = true;
      if (too_many) {
        if (P == 1) throw Error("one observed pair matches more than 2^32 map entries in one chunk");
        split(batch, first, last, consume);
        return;
      }
      if (*status_.as<std::uint32_t>() == 0) break;
      slots_ *= 4;  // overflow: nothing partial is kept; grow and rerun
      ++stats_.table_grows;
    }

    consume(first, last);
  }

  // A sub-batch without any key item: its pairs have no votes; the consumer
  // still sees them (with an empty table) so that their statistics are set.
  void consume_empty(std::size_t first, std::size_t last, const Consumer& consume) {
    const std::size_t P = last - first;
    ensure(ctx_, counters_, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
    std::memset(counters_.data(), 0, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
    ensure(ctx_, table_keys_, slots_ * sizeof(std::uint64_t));
    ensure(ctx_, table_sums_, slots_ * sizeof(std::int64_t));
    ctx_.run({}, nullptr, {{&table_keys_, 0xffffffffu, 0, slots_ * sizeof(std::uint64_t)}});
    ensure(ctx_, pairs_, P * sizeof(gpu::SvaGpuPair));
    consume(first, last);
  }

  template <class Stats>  // PairStats or PairVotes
  void set_counters(std::size_t first, std::size_t last, std::vector<Stats>& out) const {
    const auto* cnt = counters_.as<std::uint64_t>();
    for (std::size_t q = 0; q < last - first; ++q) {
      const std::uint64_t* c = cnt + SVA_PAIR_COUNTERS * q;
      out[first + q].matches = c[0];
      out[first + q].votes = c[1];
      out[first + q].votes_outside = c[2];
      out[first + q].votes_zero = c[3];
    }
  }

  // vote(): the table's sums, sorted by (pair, pose bin), as the CPU reference returns them.
  void read_back(std::size_t first, std::size_t last, std::vector<PairVotes>& out) {
    const auto* tk = table_keys_.as<std::uint64_t>();
    const auto* ts = table_sums_.as<std::int64_t>();
    std::vector<std::pair<std::uint64_t, std::int64_t>> all;
    for (std::size_t s = 0; s < slots_; ++s)
      if (tk[s] != hash::kEmptyKey) all.emplace_back(tk[s], ts[s]);
    std::sort(all.begin(), all.end());
    set_counters(first, last, out);
    for (const auto& [key, mass] : all) {
      const std::uint64_t q = bins_.pair_of(key);
      out[first + q].keys.push_back(bins_.key(bins_.bin_of(key)));
      out[first + q].mass.push_back(mass);
    }
    keep_vote_table_half_empty(all.size());
  }

  // Keep about half load next time: fewer probes, rarely a rerun.
  void keep_vote_table_half_empty(std::size_t entries) {
    slots_ = std::min(max_slots(), std::max(slots_, std::bit_ceil(std::max<std::size_t>(2 * entries, 1024))));
  }

  // The largest power-of-two vote table that one binding can hold.
  std::size_t max_slots() const {
    return std::bit_floor(static_cast<std::size_t>(ctx_.info().max_storage_buffer_range / sizeof(std::uint64_t)));
  }

  // vote_and_fold(): belief_fold.comp folds the table into the sessions'
  // beliefs on the device. A session whose table overflows (a key found no
  // slot) is skipped by the ADD pass; its table grows to hold every key its
  // pairs voted for, and only that session folds again.
  void fold(const VoteBatch& batch, std::size_t first, std::size_t last, const std::vector<GpuBelief*>& beliefs,
            std::vector<PairStats>& out) {
    const std::size_t P = last - first, S = beliefs.size();
    set_counters(first, last, out);
    ensure(ctx_, sessions_, S * sizeof(gpu::SvaGpuSession));
    ensure(ctx_, session_status_, S * sizeof(gpu::SvaGpuSessionStatus));
    ensure(ctx_, pair_totals_, 2 * P * sizeof(std::uint64_t));  // totals, then log2(total eps)
    auto* sess = sessions_.as<gpu::SvaGpuSession>();
    auto* st = session_status_.as<gpu::SvaGpuSessionStatus>();
    // Only the sessions with pairs in this sub-batch fold.
    std::vector<std::uint8_t> pending(S, 0);
    for (std::size_t q = first; q < last; ++q) pending[batch.pairs[q].session] = 1;
    std::uint64_t eps = 0;
    for (std::size_t s = 0; s < S; ++s) {
      if (!pending[s]) continue;
      if (eps != 0 && beliefs[s]->eps_units() != eps)
        throw Error("vulkan backend: all sessions of one update must use the same eps");
      eps = beliefs[s]->eps_units();
    }
    std::vector<std::uint64_t> inserted(S, 0);
    std::size_t entries = 0;  // vote-table entries, counted by the first RESERVE pass
    bool first_pass = true;
    for (;;) {
      for (std::size_t s = 0; s < S; ++s) {
        const VkDeviceAddress a = beliefs[s]->address();
        sess[s] = {gpu::lo(a), gpu::hi(a), beliefs[s]->capacity(), pending[s] ? 1u : 0u};
        st[s] = {};
      }
      std::memset(pair_totals_.data(), 0, 2 * P * sizeof(std::uint64_t));
      gpu::SvaFoldParams p{static_cast<std::uint32_t>(slots_), bins_.pair_shift(), gpu::lo(eps), gpu::hi(eps), SVA_FOLD_RESERVE,
                           static_cast<std::uint32_t>(P)};
      std::vector<vk::Dispatch> ds;
      for (std::uint32_t pass : {SVA_FOLD_RESERVE, SVA_FOLD_PAIR_LOG, SVA_FOLD_ADD}) {
        p.pass = pass;
        const vk::Grid g = ctx_.grid(pass == SVA_FOLD_PAIR_LOG ? P : slot_invocations(slots_));
        vk::Dispatch d{&fold_, {&table_keys_, &table_sums_, &pairs_, &pair_totals_, &sessions_, &session_status_}, push_bytes(p), g.x};
        d.groups_y = g.y;
        ds.push_back(std::move(d));
      }
      std::vector<double> ms;
      ctx_.run(ds, &ms);
      for (double m : ms) fold_ms_ += m;
      bool again = false;
      for (std::size_t s = 0; s < S; ++s) {
        if (!pending[s]) continue;
        if (st[s].missing) throw std::logic_error("belief_fold: a reserved key was not found");
        if (first_pass) entries += st[s].vote_entries;
        inserted[s] += st[s].inserted;
        beliefs[s]->record(st[s].inserted, 0);
        if (st[s].overflow) {
          // Room for every key the session's pairs voted for, at half load.
          beliefs[s]->grow(2 * (beliefs[s]->touched() + st[s].vote_entries));
          ++stats_.table_grows;
          again = true;
        } else {
          pending[s] = 0;
        }
      }
      first_pass = false;
      if (!again) break;
      util::throw_if_interrupted();
    }
    const auto* totals = pair_totals_.as<std::uint64_t>();
    std::vector<std::size_t> folded(S, 0);
    for (std::size_t q = 0; q < P; ++q) {
      out[first + q].folded = totals[q] > 0;
      if (totals[q] > 0) folded[batch.pairs[first + q].session] += batch.pairs[first + q].fold_count;
    }
    for (std::size_t s = 0; s < S; ++s)
      if (folded[s]) beliefs[s]->record(0, folded[s]);
    keep_vote_table_half_empty(entries);
  }

  void split(const VoteBatch& batch, std::size_t first, std::size_t last, const Consumer& consume) {
    const std::size_t mid = first + (last - first) / 2;
    vote_pairs(batch, first, mid, consume);
    vote_pairs(batch, mid, last, consume);
  }

  static vk::ContextOptions context_options(const VulkanBackendOptions& o) {
    vk::ContextOptions c = vk::Context::from_environment();
    if (!o.device.empty()) c.device = o.device;
    return c;
  }

  const PairMap& map_;
  const PoseSpace& space_;
  VoteSettings settings_;
  vk::Context ctx_;
  LinearBins bins_;
  vk::Pipeline expand_, scan_, pipeline_, fold_;
  GpuBeliefKernels beliefs_;
  vk::Buffer readings_, map_keys_, map_offsets_, pairs_, key_items_, ranges_, active_, table_keys_, table_sums_, counters_, status_;
  vk::Buffer sessions_, session_status_, pair_totals_, chunk_table_;
  double kernel_ms_ = 0.0, fold_ms_ = 0.0;
  std::vector<Chunk> chunks_;
  std::size_t chunk_ = 0, slots_ = 0;
  VulkanBackendStats stats_;

 public:
  BackendStats statistics() const override {
    return {name(), stats_.device, stats_.last_kernel_ms, stats_.last_fold_ms, stats_.last_host_ms,
            stats_.chunks, stats_.table_slots, stats_.table_grows, stats_.validation_messages};
  }
};

std::unique_ptr<VoteBackend> make_vulkan_vote_backend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings,
                                                      const VulkanBackendOptions& options) {
  return std::make_unique<VulkanVoteBackend>(map, space, settings, options);
}

}  // namespace sva
