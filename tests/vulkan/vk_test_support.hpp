#pragma once
// A Vulkan context for a GPU test, or the test ends as skipped with the reason.
#include <sva/error.hpp>

#include <memory>

#include "test_support.hpp"
#include "vulkan/context.hpp"

namespace sva::test {

inline std::unique_ptr<vk::Context> vulkan_context_or_skip() {
  try {
    return std::make_unique<vk::Context>();
  } catch (const Error& e) {
    skip(e.what());
  }
}

}  // namespace sva::test
