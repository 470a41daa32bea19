#pragma once
// One Vulkan device, its pipelines and one uploaded copy of a map, shared by
// every Vulkan backend of the process that uses the same map and device (so
// by every Recognizer and BatchRecognizer built on them): the map goes to the
// device once, however many sessions recognise with it. Backends keep their
// own work buffers (batches, vote table, beliefs); their GPU runs take turns
// on the engine's one queue (vk::Context::run locks). The map lives in the
// device's own memory, uploaded through staging where it is not host-visible.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "map/pair_map.hpp"

namespace sva {

// A slice of the map's entries that one binding can span (maxStorageBufferRange).
struct MapChunk {
  std::size_t begin = 0, count = 0;
  vk::Buffer a, b, w;  // entry_a, entry_b, entry_weight
};

class VulkanEngine {
 public:
  // The engine of (map, device, chunking), made on first use and shared while
  // any backend holds it.
  // portable_kernel: the vote kernel without subgroup pre-aggregation even
  // where the device has subgroup arithmetic (tests of both kernels).
  static std::shared_ptr<VulkanEngine> shared(const PairMap& map, const vk::ContextOptions& context,
                                              std::size_t max_chunk_entries, bool portable_kernel = false);
  // Engines alive in the process (tests of the sharing).
  static std::size_t alive();
  // The device memory the map's upload needs (before the chunk table): what an out-of-memory error names.
  static std::size_t map_device_bytes(const PairMap& map);

  VulkanEngine(const PairMap& map, const vk::ContextOptions& context, std::size_t max_chunk_entries,
               bool portable_kernel);
  ~VulkanEngine();
  VulkanEngine(const VulkanEngine&) = delete;
  VulkanEngine& operator=(const VulkanEngine&) = delete;

  vk::Context ctx;
  vk::Pipeline expand, scan, match, fold, rehash, reduce, lookup, hoods;
  vk::Buffer readings, keys, offsets, chunk_table;
  vk::Buffer no_priors;  // belief_hoods.comp's priors for every session without a pose prior (zeros: none)
  std::vector<MapChunk> chunks;
  std::size_t chunk_entries = 0;      // entries per chunk, a power of two (the last may hold fewer)
  std::size_t map_bytes = 0;          // device memory the map holds
  bool subgroup_aggregation = false;  // the vote kernel pre-aggregates equal keys per subgroup

 private:
  void upload_map(const PairMap& map, std::size_t max_chunk_entries);
};

}  // namespace sva
