#pragma once
// The GPU buffer layouts and push constants (shaders/include/sva_gpu_layout.h)
// as C++, and the small helpers every kernel launcher needs.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/vk_check.hpp"

namespace sva::gpu {
using uint = std::uint32_t;
using std::uint64_t;
#include "sva_gpu_layout.h"

// The passes' names in the device's time by kernel (vk::Dispatch::pass): belief_fold.comp's, belief_reduce.comp's and
// belief_hoods.comp's, as sva_gpu_layout.h numbers them.
inline const char* fold_pass_name(uint pass) {
  static const char* const names[] = {"reserve", "pair_log", "add", "reset", "best"};
  return pass < std::size(names) ? names[pass] : "?";
}
inline const char* reduce_pass_name(uint pass) {
  static const char* const names[] = {"mass",         "flip",   "select",      "rebuild", "table_histogram",
                                      "table_select", "bucket", "table_bucket"};
  return pass < std::size(names) ? names[pass] : "?";
}
inline const char* hoods_pass_name(uint pass) {
  static const char* const names[] = {"rank", "centres", "keys"};
  return pass < std::size(names) ? names[pass] : "?";
}

// Push-constant bytes of a parameter struct.
template <class T>
std::vector<std::uint8_t> push_bytes(const T& p) {
  std::vector<std::uint8_t> b(sizeof p);
  std::memcpy(b.data(), &p, sizeof p);
  return b;
}

// Keeps a buffer at least `bytes` large, reallocating only to grow, and then to a power of two: a batch's inputs grow
// with every update (each session's new pairs) and an estimate's selections with every touch, and on a GPU each new
// buffer is a memory allocation in its driver (counted by `sva bench`; docs/vulkan-backend.md). Exactly `bytes`
// where the power of two would pass one binding's range or the largest allocation, or does not fit.
inline void ensure(vk::Context& ctx, vk::Buffer& b, std::size_t bytes) {
  const std::size_t need = std::max<std::size_t>(bytes, 16);
  if (b.size() >= need) return;
  const std::size_t cap = std::min<std::size_t>(ctx.info().max_storage_buffer_range, ctx.info().max_allocation);
  const std::size_t want = need < cap ? std::min(std::bit_ceil(need), cap) : need;
  b = {};  // the old one's memory is free for the new one
  if (want > need) {
    try {
      b = ctx.create_buffer(want);
      return;
    } catch (const vk::OutOfMemory&) {
      // the exact size may still fit
    }
  }
  b = ctx.create_buffer(need);
}

// Where the host reads the first `bytes` of a mapped buffer `b` that the run's kernels write: `b` itself where mapped
// memory is the host's (Context::reads_through_copies), else `mirror`, a host-cached buffer kept as large as `b`, into
// which the copy added to `reads` puts them at the end of the same submission. Reading a discrete GPU's BAR in place
// costs a bus round trip per load: a batch update's counters, key ranges and statuses are tens of thousands of loads.
inline void add_mirror_read(vk::Context& ctx, const vk::Buffer& b, vk::Buffer& mirror, std::size_t bytes,
                            std::vector<vk::Copy>* reads) {
  if (!ctx.reads_through_copies()) return;
  if (mirror.size() < b.size()) mirror = ctx.create_readback_buffer(b.size());
  if (bytes > 0) reads->push_back({&b, &mirror, 0, 0, bytes});
}

// Where the host reads what add_mirror_read asked for, once its submission ran.
inline const vk::Buffer& mirror_of(const vk::Context& ctx, const vk::Buffer& b, const vk::Buffer& mirror) {
  return ctx.reads_through_copies() ? mirror : b;
}

// The halves of a 64-bit value, for push constants of 4-byte scalars.
inline std::uint32_t lo(std::uint64_t v) { return static_cast<std::uint32_t>(v & 0xffffffffu); }
inline std::uint32_t hi(std::uint64_t v) { return static_cast<std::uint32_t>(v >> 32); }

}  // namespace sva::gpu
