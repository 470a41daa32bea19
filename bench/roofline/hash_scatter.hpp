#pragma once
// The bare hash scatter of `sva bench`: fixed-point votes into a hashed
// histogram (bench/roofline/hash_scatter.comp), the vote kernel's table without
// the vote math.
// Large inputs are split into chunks that respect maxStorageBufferRange and the
// workgroup-count limit; a table overflow grows the table and reruns the whole
// scatter. The result is the exact integer sum per key, sorted by key: the same
// as the CPU reference whatever the order of atomics.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "backends/vulkan/context.hpp"

namespace sva::bench {

class HashScatter {
 public:
  explicit HashScatter(vk::Context& context, std::size_t initial_capacity = 1 << 12);
  // Votes with key == hash::kEmptyKey (all ones) are a caller bug (asserted).
  std::vector<std::pair<std::uint64_t, std::int64_t>> run(std::span<const std::uint64_t> keys,
                                                          std::span<const float> weights);
  // Largest number of votes per dispatch chunk (tests force tiny chunks).
  void set_max_chunk(std::size_t votes) { max_chunk_ = votes; }
  std::size_t capacity() const { return capacity_; }
  unsigned grow_count() const { return grows_; }
  // GPU time of the last run's kernels (0 without timestamps).
  double last_kernel_ms() const { return kernel_ms_; }

 private:
  vk::Context& ctx_;
  vk::Pipeline pipeline_;
  std::size_t capacity_;
  std::size_t max_chunk_;
  unsigned grows_ = 0;
  double kernel_ms_ = 0.0;
};

// CPU reference of the same scatter (exact integer sums per key, sorted).
std::vector<std::pair<std::uint64_t, std::int64_t>> scatter_reference(std::span<const std::uint64_t> keys,
                                                                      std::span<const float> weights);

}  // namespace sva::bench
