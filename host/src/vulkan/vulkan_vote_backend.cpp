#include "vulkan/vulkan_vote_backend.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>

#include "spv/match_votes.h"
#include "util/interrupt.hpp"
#include "vulkan/context.hpp"

namespace sva {

namespace gpu {
using uint = std::uint32_t;
using std::uint64_t;
#include "sva_gpu_layout.h"
#include "sva_hash.h"
}  // namespace gpu

namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::uint8_t> bytes_of(const gpu::SvaMatchParams& p) {
  std::vector<std::uint8_t> b(sizeof p);
  std::memcpy(b.data(), &p, sizeof p);
  return b;
}

// Keeps a buffer at least `bytes` large, reallocating only to grow.
void ensure(vk::Context& ctx, vk::Buffer& b, std::size_t bytes) {
  if (b.size() < std::max<std::size_t>(bytes, 16)) b = ctx.create_buffer(std::max<std::size_t>(bytes, 16));
}

}  // namespace

class VulkanVoteBackend final : public VoteBackend {
 public:
  VulkanVoteBackend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings, const VulkanBackendOptions& options)
      : map_(map), space_(space), settings_(settings), ctx_(context_options(options)),
        pipeline_(ctx_.create_pipeline(sva_spv_match_votes, 13, sizeof(gpu::SvaMatchParams))) {
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
    const auto& spec = space.spec();
    dim_tz_ = space.planar() ? 1u : static_cast<std::uint32_t>(spec.translation_bins);
    dim_rxy_ = space.planar() ? 1u : static_cast<std::uint32_t>(spec.rotation_bins);
    bins_total_ = std::uint64_t{space.objects()} * static_cast<std::uint64_t>(spec.translation_bins) *
                  static_cast<std::uint64_t>(spec.translation_bins) * dim_tz_ * dim_rxy_ * dim_rxy_ *
                  static_cast<std::uint64_t>(spec.rotation_bins);
  }

  const char* name() const override { return "vulkan"; }
  const VulkanBackendStats& stats() const { return stats_; }

  std::vector<PairVotes> vote(const VoteBatch& batch) override {
    const auto t0 = Clock::now();
    std::vector<PairVotes> out(batch.pairs.size());
    if (batch.pairs.empty()) return out;
    const std::size_t P = batch.pairs.size();
    if (bins_total_ > 0 && P > (UINT64_MAX >> 2) / bins_total_) throw Error("vote batch too large for 64-bit GPU keys");
    const std::uint32_t objects = space_.objects();

    // Observed pairs and the map ranges of their keys (host: a binary search each).
    ensure(ctx_, pairs_, P * sizeof(gpu::SvaGpuPair));
    auto* gp = pairs_.as<gpu::SvaGpuPair>();
    for (std::size_t q = 0; q < P; ++q) {
      const PairQuery& pq = batch.pairs[q];
      gp[q] = {pq.a.position[0], pq.a.position[1], pq.a.position[2], pq.a.norm_conf, pq.a.normal[0], pq.a.normal[1],
               pq.a.normal[2], pq.session, pq.b.position[0], pq.b.position[1], pq.b.position[2], pq.b.norm_conf,
               pq.b.normal[0], pq.b.normal[1], pq.b.normal[2], 0u};
    }
    struct Range {
      std::uint32_t item, begin, end;
    };
    std::vector<gpu::SvaGpuKeyItem> items;
    std::vector<Range> ranges;
    for (std::size_t q = 0; q < P; ++q) {
      const PairQuery& pq = batch.pairs[q];
      for (std::uint32_t k = pq.key_begin; k < pq.key_end; ++k) {
        auto [b, e] = map_.find(batch.keys[k].key);
        if (b == e) continue;
        ranges.push_back({static_cast<std::uint32_t>(items.size()), b, e});
        items.push_back({static_cast<std::uint32_t>(q), batch.keys[k].weight});
      }
    }
    ensure(ctx_, key_items_, items.size() * sizeof(gpu::SvaGpuKeyItem));
    if (!items.empty()) std::memcpy(key_items_.data(), items.data(), items.size() * sizeof(gpu::SvaGpuKeyItem));
    const std::size_t sessions = std::max<std::uint32_t>(batch.sessions, 1);
    ensure(ctx_, active_, sessions * objects * sizeof(std::uint32_t));
    auto* act = active_.as<std::uint32_t>();
    for (std::size_t i = 0; i < sessions * objects; ++i)
      act[i] = batch.object_active.empty() ? 1u : (i < batch.object_active.size() && batch.object_active[i] ? 1u : 0u);

    // Per chunk: the runs of its entries each key item matches, with offsets.
    struct ChunkWork {
      std::size_t chunk;
      std::uint32_t total, items;
    };
    std::vector<ChunkWork> plan;
    for (std::size_t c = 0; c < chunks_.size(); ++c) {
      Chunk& ch = chunks_[c];
      std::vector<gpu::SvaGpuWorkItem> work;
      std::vector<std::uint32_t> offset{0};
      std::uint64_t total = 0;
      for (const Range& r : ranges) {
        const std::size_t b = std::max<std::size_t>(r.begin, ch.begin), e = std::min<std::size_t>(r.end, ch.begin + ch.count);
        if (b >= e) continue;
        work.push_back({r.item, static_cast<std::uint32_t>(b - ch.begin)});
        total += e - b;
        if (total > UINT32_MAX) throw Error("vote batch has more than 2^32 matches in one map chunk; use smaller batches");
        offset.push_back(static_cast<std::uint32_t>(total));
      }
      if (total == 0) continue;
      ensure(ctx_, ch.work, work.size() * sizeof(gpu::SvaGpuWorkItem));
      ensure(ctx_, ch.offsets, offset.size() * sizeof(std::uint32_t));
      std::memcpy(ch.work.data(), work.data(), work.size() * sizeof(gpu::SvaGpuWorkItem));
      std::memcpy(ch.offsets.data(), offset.data(), offset.size() * sizeof(std::uint32_t));
      plan.push_back({c, static_cast<std::uint32_t>(total), static_cast<std::uint32_t>(work.size())});
    }
    ensure(ctx_, counters_, P * 3 * sizeof(std::uint64_t));
    ensure(ctx_, status_, sizeof(std::uint32_t));

    double kernel_ms = 0.0;
    for (;;) {
      util::throw_if_interrupted();
      if (slots_ * sizeof(std::uint64_t) > ctx_.info().max_storage_buffer_range)
        throw Error("GPU vote table would exceed one binding (" + std::to_string(slots_) + " slots); use smaller batches");
      ensure(ctx_, table_keys_, slots_ * sizeof(std::uint64_t));
      ensure(ctx_, table_sums_, slots_ * sizeof(std::int64_t));
      std::memset(table_keys_.data(), 0xff, slots_ * sizeof(std::uint64_t));
      std::memset(table_sums_.data(), 0, slots_ * sizeof(std::int64_t));
      std::memset(counters_.data(), 0, P * 3 * sizeof(std::uint64_t));
      *status_.as<std::uint32_t>() = 0;
      std::vector<vk::Dispatch> dispatches;
      const std::uint64_t per_dispatch = std::uint64_t{ctx_.info().max_workgroup_count_x} * SVA_WORKGROUP_SIZE;
      for (const ChunkWork& cw : plan) {
        Chunk& ch = chunks_[cw.chunk];
        for (std::uint64_t base = 0; base < cw.total; base += per_dispatch) {
          gpu::SvaMatchParams p{};
          p.base = static_cast<std::uint32_t>(base);
          p.total = cw.total;
          p.work_items = cw.items;
          p.capacity = static_cast<std::uint32_t>(slots_);
          p.objects = objects;
          const auto grid = space_.grid();
          p.grid_kind = static_cast<std::uint32_t>(grid.kind);
          p.translation_bins = grid.translation_bins;
          p.translation_min = grid.translation_min;
          p.translation_width = grid.translation_width;
          p.rotation_bins = grid.rotation_bins;
          p.rotation_width = grid.rotation_width;
          p.likelihood_cutoff = settings_.likelihood_cutoff;
          p.dim_tz = dim_tz_;
          p.dim_rxy = dim_rxy_;
          p.bins_lo = static_cast<std::uint32_t>(bins_total_ & 0xffffffffu);
          p.bins_hi = static_cast<std::uint32_t>(bins_total_ >> 32);
          const std::uint64_t n = std::min<std::uint64_t>(per_dispatch, cw.total - base);
          dispatches.push_back({&pipeline_,
                                {&pairs_, &key_items_, &ch.work, &ch.offsets, &readings_, &ch.a, &ch.b, &ch.w, &active_,
                                 &table_keys_, &table_sums_, &counters_, &status_},
                                bytes_of(p),
                                static_cast<std::uint32_t>((n + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)});
        }
      }
      std::vector<double> ms;
      ctx_.run(dispatches, &ms);
      kernel_ms = 0.0;
      for (double m : ms) kernel_ms += m;
      if (*status_.as<std::uint32_t>() == 0) break;
      slots_ *= 4;  // overflow: nothing partial is kept; grow and rerun the whole batch
      ++stats_.table_grows;
    }

    // Read back, sorted by (pair, pose bin): the linear bin order is the key order.
    const auto* tk = table_keys_.as<std::uint64_t>();
    const auto* ts = table_sums_.as<std::int64_t>();
    std::vector<std::pair<std::uint64_t, std::int64_t>> all;
    for (std::size_t s = 0; s < slots_; ++s)
      if (tk[s] != SVA_HASH_EMPTY_KEY) all.emplace_back(tk[s], ts[s]);
    std::sort(all.begin(), all.end());
    const auto* cnt = counters_.as<std::uint64_t>();
    for (std::size_t q = 0; q < P; ++q) {
      out[q].matches = cnt[3 * q];
      out[q].votes = cnt[3 * q + 1];
      out[q].votes_outside = cnt[3 * q + 2];
    }
    for (const auto& [key, mass] : all) {
      const std::uint64_t q = key / bins_total_;
      out[q].keys.push_back(bin_key(key % bins_total_));
      out[q].mass.push_back(mass);
    }
    // Keep about half load next time: fewer probes, rarely a rerun.
    slots_ = std::max(slots_, std::bit_ceil(std::max<std::size_t>(2 * all.size(), 1024)));
    stats_.table_slots = slots_;
    stats_.last_kernel_ms = kernel_ms;
    stats_.last_host_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() - kernel_ms;
    stats_.validation_messages = ctx_.validation_messages();
    return out;
  }

 private:
  struct Chunk {
    std::size_t begin = 0, count = 0;
    vk::Buffer a, b, w, work, offsets;
  };

  static vk::ContextOptions context_options(const VulkanBackendOptions& o) {
    vk::ContextOptions c = vk::Context::from_environment();
    if (!o.device.empty()) c.device = o.device;
    return c;
  }

  // Inverse of the shader's linear_bin.
  std::uint64_t bin_key(std::uint64_t linear) const {
    const auto& spec = space_.spec();
    const std::uint64_t T = static_cast<std::uint64_t>(spec.translation_bins), R = static_cast<std::uint64_t>(spec.rotation_bins);
    BinIndex b;
    b.r[2] = static_cast<int>(linear % R);
    linear /= R;
    b.r[1] = static_cast<int>(linear % dim_rxy_);
    linear /= dim_rxy_;
    b.r[0] = static_cast<int>(linear % dim_rxy_);
    linear /= dim_rxy_;
    b.t[2] = static_cast<int>(linear % dim_tz_);
    linear /= dim_tz_;
    b.t[1] = static_cast<int>(linear % T);
    linear /= T;
    b.t[0] = static_cast<int>(linear % T);
    linear /= T;
    b.object = static_cast<std::uint32_t>(linear);
    return space_.pack(b);
  }

  const PairMap& map_;
  const PoseSpace& space_;
  VoteSettings settings_;
  vk::Context ctx_;
  vk::Pipeline pipeline_;
  vk::Buffer readings_, pairs_, key_items_, active_, table_keys_, table_sums_, counters_, status_;
  std::vector<Chunk> chunks_;
  std::size_t chunk_ = 0, slots_ = 0;
  std::uint32_t dim_tz_ = 1, dim_rxy_ = 1;
  std::uint64_t bins_total_ = 0;
  VulkanBackendStats stats_;
};

std::unique_ptr<VoteBackend> make_vulkan_vote_backend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings,
                                                      const VulkanBackendOptions& options) {
  return std::make_unique<VulkanVoteBackend>(map, space, settings, options);
}

const VulkanBackendStats* vulkan_backend_stats(const VoteBackend& backend) {
  auto* v = dynamic_cast<const VulkanVoteBackend*>(&backend);
  return v ? &v->stats() : nullptr;
}

}  // namespace sva
