#pragma once
// The Vulkan backend: the same VoteBackend contract as the CPU reference, with
// the per-match work (likelihood, alignment, beta sampling, fixed-point
// scatter) in shaders/match_votes.comp, the fold into each session's belief in
// belief_fold.comp and the estimate's reductions in belief_reduce.comp; the
// beliefs stay in device memory (backends/vulkan/gpu_belief.hpp). The device and the
// map (device memory, split into chunks that respect maxStorageBufferRange)
// belong to a VulkanEngine shared by every backend of the process on the same
// map and device. A batch of pairs from any number of sessions votes and folds
// in one submission; a hash-table overflow grows the table and reruns, so no
// vote is ever dropped.
#include <map>
#include <memory>
#include <string>

#include "backends/vote_backend.hpp"

namespace sva {

struct VulkanBackendOptions {
  std::string device;  // "" = prefer a discrete GPU (env SVA_VK_DEVICE)
  // Entries per map chunk, rounded down to a power of two; 0 = as large as one binding allows (tests force tiny
  // chunks).
  std::size_t max_chunk_entries = 0;
  std::size_t initial_table_slots = 1 << 14;   // vote table (grows on overflow)
  std::size_t initial_belief_slots = 1 << 12;  // each session's belief table (grows at half load and on overflow)
  bool force_staging = false;                  // device buffers unmapped, uploads staged (env SVA_VK_STAGING=1; tests)
  bool portable_vote_kernel = false;           // no subgroup pre-aggregation even where the device has it (tests)
};

// What the backend keeps about itself; reports read it as BackendStats, through
// VoteBackend::statistics().
struct VulkanBackendStats {
  std::string device;
  std::size_t chunks = 0;    // map chunks
  unsigned table_grows = 0;  // overflow reruns so far
  std::size_t table_slots = 0;
  double last_kernel_ms = 0.0;         // GPU time of the last batch: vote kernels and fold kernels
  double last_fold_ms = 0.0;           // of which the fold into the beliefs (belief_fold.comp, growth)
  double last_host_ms = 0.0;           // host time of the last batch: preparation and read-back
  double last_belief_growth_ms = 0.0;  // of which growing the sessions' belief tables (buffers, submissions)
  double last_record_ms = 0.0, last_wait_ms = 0.0, last_device_span_ms = 0.0;  // its submissions (vk::SubmitTimes)
  std::map<std::string, BatchRecognizer::KernelTime> last_kernel_by_pipeline;  // and its kernels by pipeline
  std::uint32_t validation_messages = 0;  // Vulkan validation-layer warnings and errors (SVA_VK_VALIDATION=1)
};

class VulkanVoteBackend;
// The Vulkan device the backend would run on with these options (its name and
// type: "discrete", "integrated", "cpu", ...), and whether the caller named it
// (options or SVA_VK_DEVICE). Throws sva::Error when there is none.
struct VulkanDeviceChoice {
  std::string name, type;
  bool named = false;
};
VulkanDeviceChoice probe_vulkan_device(const VulkanBackendOptions& options = {});

std::unique_ptr<VoteBackend> make_vulkan_vote_backend(const PairMap& map, const PoseSpace& space,
                                                      const VoteSettings& settings,
                                                      const VulkanBackendOptions& options = {});

}  // namespace sva
