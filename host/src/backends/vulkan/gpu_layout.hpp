#pragma once
// The GPU buffer layouts and push constants (shaders/include/sva_gpu_layout.h)
// as C++, and the small helpers every kernel launcher needs.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "backends/vulkan/context.hpp"

namespace sva::gpu {
using uint = std::uint32_t;
using std::uint64_t;
#include "sva_gpu_layout.h"

// Push-constant bytes of a parameter struct.
template <class T>
std::vector<std::uint8_t> push_bytes(const T& p) {
  std::vector<std::uint8_t> b(sizeof p);
  std::memcpy(b.data(), &p, sizeof p);
  return b;
}

// Keeps a buffer at least `bytes` large, reallocating only to grow.
inline void ensure(vk::Context& ctx, vk::Buffer& b, std::size_t bytes) {
  if (b.size() < std::max<std::size_t>(bytes, 16)) b = ctx.create_buffer(std::max<std::size_t>(bytes, 16));
}

// The halves of a 64-bit value, for push constants of 4-byte scalars.
inline std::uint32_t lo(std::uint64_t v) { return static_cast<std::uint32_t>(v & 0xffffffffu); }
inline std::uint32_t hi(std::uint64_t v) { return static_cast<std::uint32_t>(v >> 32); }

}  // namespace sva::gpu
