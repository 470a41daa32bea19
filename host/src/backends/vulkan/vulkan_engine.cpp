#include "backends/vulkan/vulkan_engine.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <map>
#include <mutex>
#include <tuple>

#include "backends/vulkan/gpu_layout.hpp"
#include "backends/vulkan/vk_check.hpp"
#include "spv/belief_fold.h"
#include "spv/belief_hoods.h"
#include "spv/belief_lookup.h"
#include "spv/belief_reduce.h"
#include "spv/belief_rehash.h"
#include "spv/expand_pair_keys.h"
#include "spv/match_votes.h"
#include "spv/match_votes_portable.h"
#include "spv/scan_matches.h"

namespace sva {

namespace {

using Key = std::tuple<const PairMap*, std::string, bool, bool, std::size_t, bool>;

std::mutex g_registry_mutex;
std::map<Key, std::weak_ptr<VulkanEngine>> g_registry;
std::atomic<std::size_t> g_alive{0};

// The upload writes every byte, so the new buffer is not cleared first (on a discrete GPU a submission per array of
// the map); an empty array's placeholder is.
template <class T>
void upload_array(vk::Context& ctx, vk::Buffer& b, const T* data, std::size_t n) {
  b = n > 0 ? ctx.create_uncleared_device_buffer(n * sizeof(T)) : ctx.create_device_buffer(0);
  ctx.upload(b, data, n * sizeof(T));
}

}  // namespace

std::shared_ptr<VulkanEngine> VulkanEngine::shared(const PairMap& map, const vk::ContextOptions& context,
                                                   std::size_t max_chunk_entries, bool portable_kernel) {
  const Key key{&map, context.device, context.validation, context.force_staging, max_chunk_entries, portable_kernel};
  std::lock_guard lock(g_registry_mutex);
  for (auto it = g_registry.begin(); it != g_registry.end();) it = it->second.expired() ? g_registry.erase(it) : ++it;
  // A map freed while its engine lived would be a caller's bug (a backend must
  // not outlive its map), so a live entry always refers to this very map.
  // A lost device serves no new engine: a recognizer rebuilt after sva::DeviceLost gets a fresh device.
  if (auto it = g_registry.find(key); it != g_registry.end())
    if (auto e = it->second.lock(); e && !e->ctx.device().lost()) return e;
  auto e = std::make_shared<VulkanEngine>(map, context, max_chunk_entries, portable_kernel);
  g_registry[key] = e;
  return e;
}

std::size_t VulkanEngine::alive() { return g_alive.load(); }

namespace {
bool use_subgroups(const vk::Context& ctx, bool portable_kernel) {
  return ctx.info().subgroup_aggregation && !portable_kernel;
}
}  // namespace

std::size_t VulkanEngine::map_device_bytes(const PairMap& map) {
  return map.readings.size() * sizeof(gpu::SvaGpuReading) + map.keys.size() * sizeof(std::uint32_t) +
         map.offsets.size() * sizeof(map.offsets[0]) + map.entry_count() * (sizeof(std::uint32_t) * 2 + sizeof(float));
}

VulkanEngine::VulkanEngine(const PairMap& map, const vk::ContextOptions& context, std::size_t max_chunk_entries,
                           bool portable_kernel)
    : ctx(context),
      expand(ctx.create_pipeline("expand_pair_keys", sva_spv_expand_pair_keys, 4, sizeof(gpu::SvaExpandParams))),
      scan(ctx.create_pipeline("scan_matches", sva_spv_scan_matches, 3, sizeof(gpu::SvaScanParams))),
      match(use_subgroups(ctx, portable_kernel)
                ? ctx.create_pipeline("match_votes", sva_spv_match_votes, 15, sizeof(gpu::SvaMatchParams))
                : ctx.create_pipeline("match_votes_portable", sva_spv_match_votes_portable, 15,
                                      sizeof(gpu::SvaMatchParams))),
      fold(ctx.create_pipeline("belief_fold", sva_spv_belief_fold, 7, sizeof(gpu::SvaFoldParams))),
      rehash(ctx.create_pipeline("belief_rehash", sva_spv_belief_rehash, 2, sizeof(gpu::SvaRehashParams))),
      reduce(ctx.create_pipeline("belief_reduce", sva_spv_belief_reduce, 1, sizeof(gpu::SvaReduceParams))),
      lookup(ctx.create_pipeline("belief_lookup", sva_spv_belief_lookup, 1, sizeof(gpu::SvaLookupParams))),
      hoods(ctx.create_pipeline("belief_hoods", sva_spv_belief_hoods, 3, sizeof(gpu::SvaHoodParams))) {
  subgroup_aggregation = use_subgroups(ctx, portable_kernel);
  no_priors = ctx.create_buffer(64);
  std::memset(no_priors.as<std::uint8_t>(), 0, 64);
  try {
    upload_map(map, max_chunk_entries);
  } catch (const vk::OutOfMemory& e) {
    // No chunking makes a map fit: every chunk stays resident. Say what the map needs; under auto the caller
    // falls back to the CPU reference with this message.
    throw vk::OutOfMemory("the map needs " + std::to_string(map_device_bytes(map)) +
                              " bytes of GPU memory and does not fit on " + ctx.info().name + ": " + e.what(),
                          e.bytes());
  }
  ++g_alive;
}

VulkanEngine::~VulkanEngine() { --g_alive; }

void VulkanEngine::upload_map(const PairMap& map, std::size_t max_chunk_entries) {
  const std::size_t range = ctx.info().max_storage_buffer_range;
  const std::size_t range_entries = range / sizeof(std::uint32_t);
  // A power of two: the match kernel finds an entry's chunk by a shift (match_votes.glsl).
  chunk_entries = std::bit_floor(max_chunk_entries ? std::min(max_chunk_entries, range_entries) : range_entries);
  const auto& r = map.readings;
  if (r.size() * sizeof(gpu::SvaGpuReading) > range)
    throw Error("map has too many readings for one GPU binding (" + std::to_string(r.size()) + ")");
  std::vector<gpu::SvaGpuReading> g(r.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    g[i] = {r.px[i], r.py[i], r.pz[i], r.norm_conf[i], r.nx[i], r.ny[i], r.nz[i], r.object[i]};
  upload_array(ctx, readings, g.data(), g.size());
  if (map.keys.size() * sizeof(std::uint32_t) >= range)
    throw Error("map has too many keys for one GPU binding (" + std::to_string(map.keys.size()) + ")");
  upload_array(ctx, keys, map.keys.data(), map.keys.size());
  upload_array(ctx, offsets, map.offsets.data(), map.offsets.size());
  const std::size_t entries = map.entry_count();
  for (std::size_t begin = 0; begin < entries || begin == 0; begin += chunk_entries) {
    MapChunk c;
    c.begin = begin;
    c.count = std::min(chunk_entries, entries - begin);
    upload_array(ctx, c.a, map.entry_a.data() + begin, c.count);
    upload_array(ctx, c.b, map.entry_b.data() + begin, c.count);
    upload_array(ctx, c.w, map.entry_weight.data() + begin, c.count);
    map_bytes += c.a.size() + c.b.size() + c.w.size();
    chunks.push_back(std::move(c));
    if (entries == 0) break;
  }
  // The chunks' addresses, for matches that look their map pair up under the pair's other keys.
  std::vector<gpu::SvaGpuChunk> table(chunks.size());
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    const VkDeviceAddress a = chunks[i].a.device_address(), b = chunks[i].b.device_address(),
                          w = chunks[i].w.device_address();
    table[i] = {gpu::lo(a), gpu::hi(a), gpu::lo(b), gpu::hi(b), gpu::lo(w), gpu::hi(w), 0u, 0u};
  }
  upload_array(ctx, chunk_table, table.data(), table.size());
  map_bytes += readings.size() + keys.size() + offsets.size() + chunk_table.size();
}

}  // namespace sva
