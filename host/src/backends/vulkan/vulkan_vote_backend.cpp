#include "backends/vulkan/vulkan_vote_backend.hpp"

#include <sva/base/interrupt.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/gpu_belief.hpp"
#include "backends/vulkan/gpu_layout.hpp"
#include "backends/vulkan/linear_bins.hpp"
#include "backends/vulkan/vk_check.hpp"
#include "backends/vulkan/vulkan_engine.hpp"
#include "votes/bin_hash.hpp"

namespace sva {

namespace {
using Clock = std::chrono::steady_clock;
using gpu::ensure;
using gpu::push_bytes;

// Keeps a device buffer (one only kernels touch) at least `bytes` large; returns whether it was reallocated. Its
// contents are then undefined: the caller's submission clears it (a cleared buffer cost a round trip of its own, 5 of
// a cold batch's first update).
bool ensure_device(vk::Context& ctx, vk::Buffer& b, std::size_t bytes) {
  if (b.size() >= std::max<std::size_t>(bytes, 16)) return false;
  b = ctx.create_uncleared_device_buffer(std::max<std::size_t>(bytes, 16));
  return true;
}

// An observed pair as the kernels read it, with its range of key items.
gpu::SvaGpuPair gpu_pair(const PairQuery& q, std::uint32_t item_begin, std::uint32_t item_end) {
  gpu::SvaGpuPair g{};
  g.ax = q.a.position[0];
  g.ay = q.a.position[1];
  g.az = q.a.position[2];
  g.aconf = q.a.norm_conf;
  g.anx = q.a.normal[0];
  g.any = q.a.normal[1];
  g.anz = q.a.normal[2];
  g.bx = q.b.position[0];
  g.by = q.b.position[1];
  g.bz = q.b.position[2];
  g.bconf = q.b.norm_conf;
  g.bnx = q.b.normal[0];
  g.bny = q.b.normal[1];
  g.bnz = q.b.normal[2];
  g.session = q.session;
  g.fold_count = q.fold_count;
  g.item_begin = item_begin;
  g.item_end = item_end;
  return g;
}
}  // namespace

class VulkanVoteBackend final : public VoteBackend {
 public:
  VulkanVoteBackend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings,
                    const VulkanBackendOptions& options)
      : map_(map),
        space_(space),
        settings_(settings),
        engine_(VulkanEngine::shared(map, context_options(options), options.max_chunk_entries,
                                     options.portable_vote_kernel)),
        ctx_(engine_->ctx),
        bins_(space),
        beliefs_{&ctx_,
                 &space,
                 LinearBins(space),
                 &engine_->rehash,
                 &engine_->reduce,
                 &engine_->lookup,
                 &engine_->hoods,
                 &engine_->no_priors,
                 std::max<std::size_t>(options.initial_belief_slots, 64),
                 0.0} {
    stats_.device = ctx_.info().name + " (" + ctx_.info().type +
                    (engine_->subgroup_aggregation ? ", subgroup pre-aggregation" : "") + ")";
    stats_.chunks = engine_->chunks.size();
    slots_ = std::bit_ceil(std::max<std::size_t>(options.initial_table_slots, 1024));
    work_.resize(engine_->chunks.size());
  }

  const char* name() const override { return "vulkan"; }

  std::vector<PairVotes> vote(const VoteBatch& batch) override {
    std::vector<PairVotes> out(batch.pairs.size());
    timed([&] {
      Consumer c;
      c.finish = [&](std::size_t first, std::size_t last) { read_back(first, last, out); };
      vote_pairs(batch, 0, batch.pairs.size(), c);
    });
    last_work_ = work_of(out);
    return out;
  }

  std::unique_ptr<BeliefState> make_belief(const PoseSpace& space, double eps) override {
    return std::move(make_beliefs(space, eps, 1).front());
  }

  std::vector<std::unique_ptr<BeliefState>> make_beliefs(const PoseSpace& space, double eps, std::size_t n) override {
    if (&space != &space_) throw Error("vulkan backend: a belief must use the backend's pose space");
    std::vector<std::unique_ptr<BeliefState>> made;
    std::vector<GpuBelief*> fresh;
    for (std::size_t i = 0; i < n; ++i) {
      auto b = std::make_unique<GpuBelief>(beliefs_, eps);
      fresh.push_back(b.get());
      made.push_back(std::move(b));
    }
    GpuBelief::reset_all(fresh);
    return made;
  }

  std::vector<PairStats> vote_and_fold(const VoteBatch& batch, std::span<BeliefState* const> beliefs) override {
    const std::vector<GpuBelief*> gb = own<GpuBelief>(beliefs);
    for (const PairQuery& q : batch.pairs)
      if (q.session >= gb.size())
        throw Error("vulkan backend: pair of session " + std::to_string(q.session) + " has no belief");
    std::vector<PairStats> out(batch.pairs.size());
    timed([&] {
      Fold fold;
      Consumer c;
      c.prepare = [&](std::size_t first, std::size_t last) { return start_fold(batch, first, last, gb, fold); };
      c.finish = [&](std::size_t first, std::size_t last) { finish_fold(batch, first, last, gb, fold, out); };
      fold_bins_ = 0;
      vote_pairs(batch, 0, batch.pairs.size(), c);
      growing([&] { GpuBelief::keep_half_empty(gb); });  // a moved table keeps its reads ahead (the same bins)
    });
    for (const PairQuery& q : batch.pairs) gb[q.session]->end_update();
    last_work_ = work_of(out);
    last_work_.bins = fold_bins_;  // counted per session by the fold's RESERVE pass
    return out;
  }

  void read_ahead(std::span<const BeliefState* const> beliefs, std::size_t best_bins,
                  std::span<const KeyChoice> keys) override {
    if (!keys.empty() && keys.size() != beliefs.size())
      throw std::logic_error("vulkan backend: read_ahead needs a key choice per belief");
    GpuBelief::read_ahead(own<const GpuBelief>(beliefs), best_bins, keys);
  }

  void look_up_ahead(std::span<const BeliefState* const> beliefs,
                     std::span<const std::vector<std::uint64_t>> keys) override {
    if (keys.size() != beliefs.size()) throw std::logic_error("vulkan backend: look_up_ahead needs keys per belief");
    GpuBelief::look_up_ahead(own<const GpuBelief>(beliefs), keys);
  }

  void reset_beliefs(std::span<BeliefState* const> beliefs) override { GpuBelief::reset_all(own<GpuBelief>(beliefs)); }

  // Device memory: what the engine's device holds (the map once, and the work buffers and beliefs of every
  // backend sharing the engine; tables only grow, so this is the peak of the run so far).
  BackendStats statistics() const override {
    BackendStats s{
        name(),        stats_.device,      stats_.last_kernel_ms, stats_.last_fold_ms,       stats_.last_host_ms,
        stats_.chunks, stats_.table_slots, stats_.table_grows,    stats_.validation_messages};
    s.device_bytes = ctx_.device().device_bytes();
    s.map_device_bytes = engine_->map_bytes;
    s.device_held_bytes = ctx_.device().pool().held_bytes();
    s.band_rebuilds = beliefs_.band_rebuilds;
    s.last_work = last_work_;
    s.last_belief_growth_ms = stats_.last_belief_growth_ms;
    s.last_record_ms = stats_.last_record_ms;
    s.last_wait_ms = stats_.last_wait_ms;
    s.last_device_span_ms = stats_.last_device_span_ms;
    s.last_kernel_by_pipeline = stats_.last_kernel_by_pipeline;
    s.device_submissions = ctx_.submissions();
    s.device_allocations = ctx_.allocations();
    s.device_type = ctx_.info().type;
    s.device_memory_bytes = ctx_.info().device_local_bytes;
    return s;
  }

 private:
  // The beliefs as this backend's own (each made by make_belief); G is GpuBelief or const GpuBelief.
  template <class G, class State>
  static std::vector<G*> own(std::span<State* const> beliefs) {
    std::vector<G*> gb;
    for (State* b : beliefs) {
      G* g = dynamic_cast<G*>(b);
      if (!g) throw Error("vulkan backend: a session's belief was made by another backend");
      gb.push_back(g);
    }
    return gb;
  }

  // The last update's work: the device's counters, the ranges of map entries it found, the fold's vote-table entries
  // (the belief probes are not counted on the device: 0).
  BatchRecognizer::Work last_work_;
  std::size_t key_items_count_ = 0;  // of the sub-batch last uploaded
  std::uint64_t fold_bins_ = 0;      // of the update so far

  // Per map chunk: the scan of a batch's matches and its indirect dispatch.
  struct ChunkWork {
    vk::Buffer offsets, scan;
    vk::Buffer scan_mirror;  // where the host reads `scan` (gpu::add_mirror_read)
  };

  // What a consumer adds to a sub-batch's vote submission: dispatches run right after the votes, fills before them
  // and copies of results after them.
  struct Added {
    std::vector<vk::Dispatch> dispatches;
    std::vector<vk::Fill> fills;
    std::vector<vk::Copy> reads;
  };

  // What a sub-batch's consumer adds to the vote submission (prepare) and does once it succeeded (finish).
  struct Consumer {
    std::function<Added(std::size_t, std::size_t)> prepare;
    std::function<void(std::size_t, std::size_t)> finish;
  };

  // The fold of one sub-batch: which sessions still fold, and their eps; which read their estimate's summary ahead in
  // its submission (GpuBelief::add_reads_after_fold).
  struct Fold {
    std::vector<std::uint8_t> pending, read_ahead;
    std::uint64_t eps = 0;
  };

  template <class Fn>
  void timed(Fn&& fn) {
    const auto t0 = Clock::now();
    kernel_ms_ = 0.0;
    fold_ms_ = 0.0;
    growth_ms_ = 0.0;
    beliefs_.kernel_ms = 0.0;
    const vk::SubmitTimes s0 = ctx_.submit_times();
    fn();
    const vk::SubmitTimes s1 = ctx_.submit_times();
    fold_ms_ += beliefs_.kernel_ms;  // table growth during the fold
    kernel_ms_ += fold_ms_;
    stats_.last_fold_ms = fold_ms_;
    stats_.table_slots = slots_;
    stats_.last_kernel_ms = kernel_ms_;
    stats_.last_host_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() - kernel_ms_;
    stats_.last_record_ms = s1.record_ms - s0.record_ms;
    stats_.last_wait_ms = s1.wait_ms - s0.wait_ms;
    stats_.last_device_span_ms = s1.span_ms - s0.span_ms;
    stats_.last_kernel_by_pipeline.clear();
    for (const auto& [name, k] : vk::kernel_times_since(s0.kernels, s1.kernels))
      stats_.last_kernel_by_pipeline[name] = {k.ms, k.dispatches};
    stats_.last_belief_growth_ms = growth_ms_;
    stats_.validation_messages = ctx_.validation_messages();
  }

  // Runs fn, which grows belief tables, and counts its host time (its wall time less the growth's kernels) in
  // growth_ms_: in a batch each growing session pays a new buffer and its submissions, a suspect for the batch's host
  // time on a GPU (docs/vulkan-backend.md, "The fifth GPU run").
  template <class Fn>
  void growing(Fn&& fn) {
    const auto t0 = Clock::now();
    const double kernels = beliefs_.kernel_ms;
    fn();
    const double wall = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    growth_ms_ += std::max(0.0, wall - (beliefs_.kernel_ms - kernels));  // two clocks: never below 0
  }

  // The key items of pairs [first, last) (their map keys, weights, and each
  // pair's range of items); false when the sub-batch must be split.
  bool upload_inputs(const VoteBatch& batch, std::size_t first, std::size_t last, std::size_t* key_items) {
    const std::size_t P = last - first;
    std::vector<gpu::SvaGpuKeyItem> items;
    std::vector<std::uint32_t> item_begin(P + 1, 0);
    for (std::size_t q = first; q < last; ++q) {
      item_begin[q - first] = static_cast<std::uint32_t>(std::min<std::size_t>(items.size(), SVA_MAX_KEY_ITEMS + 1));
      for (std::uint32_t k = batch.pairs[q].key_begin; k < batch.pairs[q].key_end; ++k)
        items.push_back(
            {static_cast<std::uint32_t>(q - first), batch.keys[k].key, batch.keys[k].weight, batch.keys[k].reversed});
    }
    *key_items = items.size();
    key_items_count_ = items.size();
    item_pairs_.resize(items.size());  // set_counters' view of the items: the host's own, not the mapped buffer
    for (std::size_t k = 0; k < items.size(); ++k) item_pairs_[k] = items[k].pair;
    if ((items.size() > SVA_MAX_KEY_ITEMS || P > bins_.max_pairs()) && P > 1) return false;
    if (items.size() > SVA_MAX_KEY_ITEMS)
      throw Error("one observed pair has more map keys than the GPU backend handles");
    item_begin[P] = static_cast<std::uint32_t>(items.size());
    ensure(ctx_, pairs_, P * sizeof(gpu::SvaGpuPair));
    auto* gp = pairs_.as<gpu::SvaGpuPair>();
    for (std::size_t q = 0; q < P; ++q) {
      gp[q] = gpu_pair(batch.pairs[first + q], item_begin[q], item_begin[q + 1]);
    }
    ensure(ctx_, key_items_, items.size() * sizeof(gpu::SvaGpuKeyItem));
    if (!items.empty()) std::memcpy(key_items_.data(), items.data(), items.size() * sizeof(gpu::SvaGpuKeyItem));
    ensure(ctx_, ranges_, items.size() * sizeof(gpu::SvaGpuRange));
    const std::uint32_t objects = space_.objects();
    const std::size_t sessions = std::max<std::uint32_t>(batch.sessions, 1);
    ensure(ctx_, active_, sessions * objects * sizeof(std::uint32_t));
    auto* act = active_.as<std::uint32_t>();
    for (std::size_t i = 0; i < sessions * objects; ++i)
      act[i] = batch.object_active.empty() ? 1u : (i < batch.object_active.size() && batch.object_active[i] ? 1u : 0u);
    for (ChunkWork& w : work_) {
      ensure(ctx_, w.offsets, (items.size() + 1) * sizeof(std::uint32_t));
      ensure(ctx_, w.scan, sizeof(gpu::SvaScanResult));
    }
    ensure(ctx_, counters_, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
    ensure(ctx_, status_, sizeof(std::uint32_t));
    return true;
  }

  gpu::SvaMatchParams match_params(std::size_t key_items, const MapChunk& chunk) const {
    const auto grid = space_.grid();
    gpu::SvaMatchParams p{};
    p.key_items = static_cast<std::uint32_t>(key_items);
    p.chunk_begin = static_cast<std::uint32_t>(chunk.begin);
    p.chunk_end = static_cast<std::uint32_t>(chunk.begin + chunk.count);
    p.capacity = static_cast<std::uint32_t>(slots_);
    p.objects = space_.objects();
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
    p.chunk_shift = static_cast<std::uint32_t>(std::countr_zero(engine_->chunk_entries));
    return p;
  }

  // Expand keys to map ranges, then per map chunk a scan of its matches and the indirect match kernel.
  std::vector<vk::Dispatch> vote_dispatches(std::size_t key_items) {
    VulkanEngine& e = *engine_;
    std::vector<vk::Dispatch> ds;
    gpu::SvaExpandParams ep{static_cast<std::uint32_t>(key_items), static_cast<std::uint32_t>(map_.keys.size())};
    ds.push_back({&e.expand,
                  {&key_items_, &e.keys, &e.offsets, &ranges_},
                  push_bytes(ep),
                  static_cast<std::uint32_t>((key_items + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)});
    for (std::size_t c = 0; c < e.chunks.size(); ++c) {
      MapChunk& ch = e.chunks[c];
      ChunkWork& w = work_[c];
      if (ch.count == 0) continue;
      gpu::SvaScanParams sp{static_cast<std::uint32_t>(key_items), static_cast<std::uint32_t>(ch.begin),
                            static_cast<std::uint32_t>(ch.begin + ch.count), ctx_.info().max_workgroup_count_x};
      ds.push_back({&e.scan, {&ranges_, &w.offsets, &w.scan}, push_bytes(sp), 1});
      vk::Dispatch d{&e.match,
                     {&pairs_, &key_items_, &ranges_, &w.offsets, &e.readings, &ch.a, &ch.b, &ch.w, &active_,
                      &table_keys_, &table_sums_, &counters_, &status_, &w.scan, &e.chunk_table},
                     push_bytes(match_params(key_items, ch)),
                     0};
      d.indirect = &w.scan;
      ds.push_back(std::move(d));
    }
    return ds;
  }

  // Clears of the vote table when it is not known to be clean (the fold
  // clears every slot it folds, so an update normally needs none).
  std::vector<vk::Fill> table_clears() {
    if (ensure_device(ctx_, table_keys_, slots_ * sizeof(std::uint64_t))) table_dirty_ = true;
    if (ensure_device(ctx_, table_sums_, slots_ * sizeof(std::int64_t))) table_dirty_ = true;
    if (!table_dirty_) return {};
    // The whole buffers, not only the slots in use: the table may grow into them later.
    return {{&table_keys_, 0xffffffffu, 0, 0}, {&table_sums_, 0u, 0, 0}};
  }

  // Votes of pairs [first, last) of the batch into the vote table and the
  // consumer's dispatches, in one submission; then the consumer's finish while
  // the table holds them. A batch too large for one pass (key items, table or
  // 2^32 matches in a chunk) is split in halves; a table overflow grows it and
  // runs again (nothing partial is kept).
  void vote_pairs(const VoteBatch& batch, std::size_t first, std::size_t last, const Consumer& consume) {
    if (first >= last) return;
    const std::size_t P = last - first;
    std::size_t K = 0;
    try {
      if (!upload_inputs(batch, first, last, &K)) return split(batch, first, last, consume);
    } catch (const vk::OutOfMemory&) {
      if (P == 1) throw;
      return split(batch, first, last, consume);  // chunk further: half the pairs need half the input buffers
    }
    for (;;) {
      util::throw_if_interrupted();
      if (slots_ > max_slots()) {
        if (P > 1) {
          slots_ = max_slots();  // each half starts from the largest table one binding holds
          return split(batch, first, last, consume);
        }
        throw Error("GPU vote table would exceed one binding or the device memory (" + std::to_string(slots_) +
                    " slots) for one pair");
      }
      std::vector<vk::Fill> clear;
      try {
        clear = table_clears();
      } catch (const vk::OutOfMemory& e) {
        // Chunk further: the halves need smaller tables; the largest that fitted becomes the cap.
        if (P > 1 && slots_ > kMinSlots) {
          slot_cap_ = std::max(kMinSlots, slots_ / 4);
          slots_ = slot_cap_;
          return split(batch, first, last, consume);
        }
        throw vk::OutOfMemory("the GPU vote table of one pair (" + std::to_string(slots_) + " slots, " +
                                  std::to_string(slots_ * 16) + " bytes) does not fit: " + e.what(),
                              e.bytes());
      }
      *status_.as<std::uint32_t>() = 0;
      std::memset(counters_.data(), 0, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t));
      std::vector<vk::Dispatch> ds;
      if (K > 0) ds = vote_dispatches(K);
      const std::size_t votes = ds.size();
      Added added;
      if (consume.prepare) added = consume.prepare(first, last);
      for (vk::Dispatch& d : added.dispatches) ds.push_back(std::move(d));
      clear.insert(clear.end(), added.fills.begin(), added.fills.end());
      table_dirty_ = true;  // until a fold has cleared what the votes wrote
      std::vector<vk::Copy> reads = vote_reads(P, K);
      reads.insert(reads.end(), added.reads.begin(), added.reads.end());
      std::vector<double> ms;
      ctx_.run(ds, &ms, clear, reads);
      for (std::size_t i = 0; i < ms.size(); ++i) (i < votes ? kernel_ms_ : fold_ms_) += ms[i];
      bool too_many = false;
      for (std::size_t c = 0; c < work_.size() && K > 0; ++c)
        if (engine_->chunks[c].count && read(work_[c].scan, work_[c].scan_mirror).as<gpu::SvaScanResult>()->too_many)
          too_many = true;
      if (too_many) {
        if (P == 1) throw Error("one observed pair matches more than 2^32 map entries in one chunk");
        return split(batch, first, last, consume);
      }
      if (*read(status_, status_mirror_).as<std::uint32_t>() == 0) break;
      slots_ *= 4;  // overflow: the fold passes saw the flag and did nothing; grow and rerun
      ++stats_.table_grows;
    }
    consume.finish(first, last);
  }

  // The copies of the votes' results that the host reads after their submission (gpu::add_mirror_read): the
  // overflow flag, each pair's counters, each key item's map range and each chunk's scan.
  std::vector<vk::Copy> vote_reads(std::size_t P, std::size_t key_items) {
    std::vector<vk::Copy> r;
    gpu::add_mirror_read(ctx_, status_, status_mirror_, sizeof(std::uint32_t), &r);
    gpu::add_mirror_read(ctx_, counters_, counters_mirror_, P * SVA_PAIR_COUNTERS * sizeof(std::uint64_t), &r);
    gpu::add_mirror_read(ctx_, ranges_, ranges_mirror_, key_items * sizeof(gpu::SvaGpuRange), &r);
    for (ChunkWork& w : work_) gpu::add_mirror_read(ctx_, w.scan, w.scan_mirror, sizeof(gpu::SvaScanResult), &r);
    return r;
  }

  // Where the host reads what the last submission wrote into the mapped buffer `b` (its mirror on a discrete GPU).
  const vk::Buffer& read(const vk::Buffer& b, const vk::Buffer& mirror) const {
    return gpu::mirror_of(ctx_, b, mirror);
  }

  template <class Stats>  // PairStats or PairVotes
  void set_counters(std::size_t first, std::size_t last, std::vector<Stats>& out) const {
    const auto* cnt = read(counters_, counters_mirror_).as<std::uint64_t>();
    for (std::size_t q = 0; q < last - first; ++q) {
      const std::uint64_t* c = cnt + SVA_PAIR_COUNTERS * q;
      out[first + q].matches = c[0];
      out[first + q].votes = c[1];
      out[first + q].votes_outside = c[2];
      out[first + q].votes_zero = c[3];
      out[first + q].table_probes = c[5];
      out[first + q].atomics = c[4] + c[5];
    }
    // The map entries under each pair's keys: the ranges expand_pair_keys found.
    const auto* ranges = read(ranges_, ranges_mirror_).as<gpu::SvaGpuRange>();
    for (std::size_t k = 0; k < key_items_count_; ++k)
      out[first + item_pairs_[k]].entries += ranges[k].end - ranges[k].begin;
  }

  // vote(): the table's sums, sorted by (pair, pose bin), as the CPU reference returns them.
  void read_back(std::size_t first, std::size_t last, std::vector<PairVotes>& out) {
    std::vector<std::uint64_t> tk(slots_);
    std::vector<std::int64_t> ts(slots_);
    ctx_.download(table_keys_, tk.data(), slots_ * sizeof(std::uint64_t));
    ctx_.download(table_sums_, ts.data(), slots_ * sizeof(std::int64_t));
    std::vector<std::pair<std::uint64_t, std::int64_t>> all;
    for (std::size_t s = 0; s < slots_; ++s)
      if (tk[s] != hash::kEmptyKey) all.emplace_back(tk[s], ts[s]);
    std::sort(all.begin(), all.end());
    set_counters(first, last, out);
    for (const auto& [key, mass] : all) {
      const std::uint64_t q = bins_.pair_of(key);
      out[first + q].keys.push_back(bins_.key(bins_.bin_of(key)));
      out[first + q].mass.push_back(mass);
      ++out[first + q].bins;
    }
    keep_vote_table_half_empty(all.size());
  }

  // Keep about half load next time: fewer probes, rarely a rerun. The fold
  // passes visit every slot in use, so a table far larger than the last
  // update needed (a session reset, a new trial) shrinks back to 4x that (its
  // buffer stays, clean, for when votes grow again).
  void keep_vote_table_half_empty(std::size_t entries) {
    const std::size_t want = std::bit_ceil(std::max<std::size_t>(2 * entries, 1024));
    if (8 * want <= slots_) slots_ = 4 * want;
    slots_ = std::min(max_slots(), std::max(slots_, want));
  }

  // The largest power-of-two vote table that one binding can hold (and, once an allocation failed, that fitted).
  std::size_t max_slots() const {
    return std::min(slot_cap_, std::bit_floor(static_cast<std::size_t>(ctx_.info().max_storage_buffer_range /
                                                                       sizeof(std::uint64_t))));
  }

  // The fold passes of belief_fold.comp for the pending sessions: RESERVE,
  // PAIR_LOG, ADD (which also raises the maxima), RESET and BEST, which keep
  // each session's estimate state current (BEST clears every slot it folds).
  std::vector<vk::Dispatch> fold_dispatches(std::size_t P, const std::vector<GpuBelief*>& beliefs, const Fold& fold) {
    const std::size_t S = beliefs.size();
    auto* sess = sessions_.as<gpu::SvaGpuSession>();
    auto* st = session_status_.as<gpu::SvaGpuSessionStatus>();
    for (std::size_t s = 0; s < S; ++s) {
      const GpuBelief& b = *beliefs[s];
      sess[s] = {gpu::lo(b.address()),      gpu::hi(b.address()),       b.capacity(),
                 fold.pending[s] ? 1u : 0u, gpu::lo(b.state_address()), gpu::hi(b.state_address()),
                 gpu::lo(b.band_address()), gpu::hi(b.band_address()),  b.band_capacity(),
                 gpu::lo(b.band_floor()),   gpu::hi(b.band_floor()),    0u};
      st[s] = {};
    }
    std::memset(pair_totals_.data(), 0, 2 * P * sizeof(std::uint64_t));
    gpu::SvaFoldParams p{};
    p.slots = static_cast<std::uint32_t>(slots_);
    p.pair_shift = bins_.pair_shift();
    p.eps_lo = gpu::lo(fold.eps);
    p.eps_hi = gpu::hi(fold.eps);
    p.pairs = static_cast<std::uint32_t>(P);
    p.sessions = static_cast<std::uint32_t>(S);
    p.objects = space_.objects();
    p.object_shift = bins_.object_shift();
    const std::uint64_t band_width = S > 0 ? beliefs[0]->band_width() : 0;  // one pose space: one width
    p.band_width_lo = gpu::lo(band_width);
    p.band_width_hi = gpu::hi(band_width);
    std::vector<vk::Dispatch> ds;
    for (std::uint32_t pass : {SVA_FOLD_RESERVE, SVA_FOLD_PAIR_LOG, SVA_FOLD_ADD, SVA_FOLD_RESET, SVA_FOLD_BEST}) {
      p.pass = pass;
      const std::uint64_t invocations = pass == SVA_FOLD_PAIR_LOG ? P
                                        : pass == SVA_FOLD_RESET  ? S * std::uint64_t{space_.objects()}
                                                                  : slot_invocations(slots_);
      const vk::Grid g = ctx_.grid(invocations);
      vk::Dispatch d{&engine_->fold,
                     {&table_keys_, &table_sums_, &pairs_, &pair_totals_, &sessions_, &session_status_, &status_},
                     push_bytes(p),
                     g.x};
      d.groups_y = g.y;
      d.pass = gpu::fold_pass_name(pass);
      ds.push_back(std::move(d));
    }
    return ds;
  }

  // vote_and_fold(), before the vote submission: the sessions with pairs in
  // [first, last) fold, with their common eps; the first fold runs in the
  // votes' submission, and after it the reads ahead of the sessions whose last estimate asked for them.
  Added start_fold(const VoteBatch& batch, std::size_t first, std::size_t last, const std::vector<GpuBelief*>& beliefs,
                   Fold& fold) {
    const std::size_t P = last - first, S = beliefs.size();
    ensure(ctx_, sessions_, S * sizeof(gpu::SvaGpuSession));
    ensure(ctx_, session_status_, S * sizeof(gpu::SvaGpuSessionStatus));
    ensure(ctx_, pair_totals_, 2 * P * sizeof(std::uint64_t));  // totals, then log2(total eps)
    fold.pending.assign(S, 0);
    for (std::size_t q = first; q < last; ++q) fold.pending[batch.pairs[q].session] = 1;
    fold.eps = 0;
    for (std::size_t s = 0; s < S; ++s) {
      if (!fold.pending[s]) continue;
      if (fold.eps != 0 && beliefs[s]->eps_units() != fold.eps)
        throw Error("vulkan backend: all sessions of one update must use the same eps");
      fold.eps = beliefs[s]->eps_units();
    }
    Added a;
    a.dispatches = fold_dispatches(P, beliefs, fold);
    fold_reads(P, S, &a.reads);
    fold.read_ahead.assign(S, 0);
    std::vector<std::size_t> folding;
    for (std::size_t s = 0; s < S; ++s)
      if (fold.pending[s]) folding.push_back(s);
    add_reads_ahead(beliefs, folding, fold, &a);
    return a;
  }

  // After their fold, the reads ahead of `sessions` that an estimate asked for (GpuBelief::add_reads_after_fold), each
  // session's passes side by side with the others' (vk::side_by_side: each touches its own belief only), marked in
  // fold.read_ahead.
  void add_reads_ahead(const std::vector<GpuBelief*>& beliefs, const std::vector<std::size_t>& sessions, Fold& fold,
                       Added* a) {
    std::vector<std::vector<vk::Dispatch>> ahead(sessions.size());
    for (std::size_t i = 0; i < sessions.size(); ++i)
      if (beliefs[sessions[i]]->add_reads_after_fold(&ahead[i], &a->fills, &a->reads)) fold.read_ahead[sessions[i]] = 1;
    for (vk::Dispatch& d : vk::side_by_side(std::move(ahead))) a->dispatches.push_back(std::move(d));
  }

  // The copies of the fold's results that finish_fold reads (gpu::add_mirror_read): each session's status and each
  // pair's total.
  void fold_reads(std::size_t P, std::size_t S, std::vector<vk::Copy>* reads) {
    gpu::add_mirror_read(ctx_, session_status_, session_status_mirror_, S * sizeof(gpu::SvaGpuSessionStatus), reads);
    gpu::add_mirror_read(ctx_, pair_totals_, pair_totals_mirror_, P * sizeof(std::uint64_t), reads);
  }

  // After the submission: a session whose belief table overflowed (a key found
  // no slot) was skipped by the ADD pass and kept its vote-table slots; its
  // table grows to hold every key its pairs voted for, and it alone folds again.
  void finish_fold(const VoteBatch& batch, std::size_t first, std::size_t last, const std::vector<GpuBelief*>& beliefs,
                   Fold& fold, std::vector<PairStats>& out) {
    const std::size_t P = last - first, S = beliefs.size();
    set_counters(first, last, out);
    const auto* totals = read(pair_totals_, pair_totals_mirror_).as<std::uint64_t>();
    std::vector<std::size_t> folded(S, 0);
    for (std::size_t q = 0; q < P; ++q) {
      out[first + q].folded = totals[q] > 0;
      if (totals[q] > 0) folded[batch.pairs[first + q].session] += batch.pairs[first + q].fold_count;
    }
    const auto statuses = [&] { return read(session_status_, session_status_mirror_).as<gpu::SvaGpuSessionStatus>(); };
    std::size_t entries = 0;  // vote-table entries, counted by the first RESERVE pass
    for (std::size_t s = 0; s < S; ++s)
      if (fold.pending[s]) entries += statuses()[s].vote_entries;
    fold_bins_ += entries;
    for (;;) {
      const gpu::SvaGpuSessionStatus* st = statuses();  // this round's fold's
      std::vector<std::size_t> full;  // sessions whose table overflowed: they grow together, then fold again
      for (std::size_t s = 0; s < S; ++s) {
        if (!fold.pending[s]) continue;
        if (st[s].missing) throw std::logic_error("belief_fold: a reserved key was not found");
        beliefs[s]->record(st[s].inserted, 0);
        if (st[s].overflow) {
          full.push_back(s);
          fold.read_ahead[s] = 0;  // its reads ran before its fold was complete
        } else {
          fold.pending[s] = 0;
        }
      }
      if (full.empty()) break;
      growing([&] { grow_beliefs(beliefs, full, st); });
      stats_.table_grows += full.size();
      util::throw_if_interrupted();
      Added again;  // the grown sessions' fold, and their reads ahead after it
      again.dispatches = fold_dispatches(P, beliefs, fold);
      fold_reads(P, S, &again.reads);
      add_reads_ahead(beliefs, full, fold, &again);
      std::vector<double> ms;
      ctx_.run(again.dispatches, &ms, again.fills, again.reads);
      for (double m : ms) fold_ms_ += m;
    }
    std::vector<const GpuBelief*> ahead;
    for (std::size_t s = 0; s < S; ++s) {
      if (folded[s]) beliefs[s]->record(0, folded[s]);
      if (fold.read_ahead[s]) ahead.push_back(beliefs[s]);
    }
    GpuBelief::keep_reads_after_fold(ahead);
    table_dirty_ = false;  // every slot was folded, and cleared
    keep_vote_table_half_empty(entries);
  }

  // The sessions `full` of a fold that found their tables full, grown together to hold every key their pairs voted
  // for at half load. A session's belief cannot be split: when its table does not fit, say how large it is and what
  // bounds it.
  static void grow_beliefs(const std::vector<GpuBelief*>& beliefs, const std::vector<std::size_t>& full,
                           const gpu::SvaGpuSessionStatus* st) {
    std::vector<GpuBelief*> grow;
    std::vector<std::uint64_t> slots;
    for (std::size_t s : full) {
      grow.push_back(beliefs[s]);
      slots.push_back(2 * (beliefs[s]->touched() + st[s].vote_entries));
    }
    GpuBelief::grow_all(grow, slots, [&](std::size_t i, const vk::OutOfMemory& e) {
      throw vk::OutOfMemory(
          "the GPU belief of session " + std::to_string(full[i]) + " (" + std::to_string(grow[i]->touched()) +
              " touched pose bins, growing to " + std::to_string(slots[i]) +
              " slots) does not fit; a smaller RecognizerOptions::belief_budget_bins bounds it: " + e.what(),
          e.bytes());
    });
  }

  void split(const VoteBatch& batch, std::size_t first, std::size_t last, const Consumer& consume) {
    const std::size_t mid = first + (last - first) / 2;
    vote_pairs(batch, first, mid, consume);
    vote_pairs(batch, mid, last, consume);
  }

  static vk::ContextOptions context_options(const VulkanBackendOptions& o) {
    vk::ContextOptions c = vk::Context::from_environment();
    if (!o.device.empty()) c.device = o.device;
    if (o.force_staging) c.force_staging = true;
    return c;
  }

  const PairMap& map_;
  const PoseSpace& space_;
  VoteSettings settings_;
  std::shared_ptr<VulkanEngine> engine_;  // the device and the uploaded map, shared with other backends
  vk::Context& ctx_;
  LinearBins bins_;
  GpuBeliefKernels beliefs_;
  vk::Buffer pairs_, key_items_, ranges_, active_, counters_, status_;  // a batch's inputs and outputs (mapped)
  vk::Buffer table_keys_, table_sums_;                                  // the vote table (device memory)
  vk::Buffer sessions_, session_status_, pair_totals_;
  // Host-cached copies of the mapped outputs above, where the host reads them on a discrete GPU (gpu::add_mirror_read).
  vk::Buffer status_mirror_, counters_mirror_, ranges_mirror_, session_status_mirror_, pair_totals_mirror_;
  std::vector<std::uint32_t> item_pairs_;  // each key item's pair (of the last upload_inputs)
  bool table_dirty_ = true;                // the vote table may hold keys: clear it before the next votes
  double kernel_ms_ = 0.0, fold_ms_ = 0.0, growth_ms_ = 0.0;
  std::vector<ChunkWork> work_;
  std::size_t slots_ = 0;
  static constexpr std::size_t kMinSlots = 1024;
  std::size_t slot_cap_ = SIZE_MAX;  // the vote table's slots after an allocation failed (chunk further)
  VulkanBackendStats stats_;
};

VulkanDeviceChoice probe_vulkan_device(const VulkanBackendOptions& options) {
  vk::ContextOptions o = vk::Context::from_environment();
  if (!options.device.empty()) o.device = options.device;
  const vk::Instance instance(false);
  const vk::Device device(instance, o.device);
  return {device.info().name, device.info().type, !o.device.empty()};
}

std::unique_ptr<VoteBackend> make_vulkan_vote_backend(const PairMap& map, const PoseSpace& space,
                                                      const VoteSettings& settings,
                                                      const VulkanBackendOptions& options) {
  return std::make_unique<VulkanVoteBackend>(map, space, settings, options);
}

}  // namespace sva
