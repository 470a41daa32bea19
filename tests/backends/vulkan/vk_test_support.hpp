#pragma once
// A Vulkan context for a GPU test, or the test ends as skipped with the reason.
#include <sva/error.hpp>

#include <memory>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/vulkan_vote_backend.hpp"
#include "test_support.hpp"

namespace sva::test {

inline std::unique_ptr<vk::Context> vulkan_context_or_skip() {
  try {
    return std::make_unique<vk::Context>();
  } catch (const Error& e) {
    skip(e.what());
  }
}

// A Vulkan vote backend, or the test ends as skipped with the reason.
inline std::unique_ptr<VoteBackend> vulkan_backend_or_skip(const PairMap& map, const PoseSpace& space,
                                                           const VoteSettings& vs, const VulkanBackendOptions& o = {}) {
  try {
    return make_vulkan_vote_backend(map, space, vs, o);
  } catch (const Error& e) {
    skip(e.what());
  }
}

}  // namespace sva::test
