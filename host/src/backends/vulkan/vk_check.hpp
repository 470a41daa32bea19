#pragma once
// Every Vulkan call's result goes through check(): the one place that turns a
// VkResult into an error. A lost device becomes sva::DeviceLost (the session
// can be rebuilt from its readings, docs/reliability.md), exhausted
// memory vk::OutOfMemory (callers that can chunk further catch it), anything
// else an sva::Error naming the call and the result.
#include <vulkan/vulkan.h>

#include <sva/error.hpp>

#include <cstddef>
#include <string>

namespace sva::vk {

// VK_ERROR_OUT_OF_DEVICE_MEMORY or VK_ERROR_OUT_OF_HOST_MEMORY from the driver
// (or from the injected allocation budget, backends/vulkan/faults.hpp).
class OutOfMemory : public Error {
 public:
  OutOfMemory(const std::string& what, std::size_t bytes) : Error(what), bytes_(bytes) {}
  std::size_t bytes() const { return bytes_; }  // the allocation that failed (0 when not an allocation)

 private:
  std::size_t bytes_;
};

// "VK_ERROR_DEVICE_LOST" etc.; the number for a result this build does not name.
std::string result_name(VkResult r);

[[noreturn]] void fail(VkResult r, const char* what);
inline void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) fail(r, what);
}

}  // namespace sva::vk
