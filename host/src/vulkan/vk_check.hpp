#pragma once
// Every Vulkan call's result is checked; a failure is an sva::Error naming the call.
#include <vulkan/vulkan.h>

#include <sva/error.hpp>

#include <string>

namespace sva::vk {

inline void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw Error(std::string("Vulkan: ") + what + " failed (VkResult " + std::to_string(r) + ")");
}

}  // namespace sva::vk
