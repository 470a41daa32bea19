#pragma once
// The Vulkan instance: the loader's entry point, with the Khronos validation
// layer and a log of its warnings and errors when asked for (tests treat any
// such message as a failure).
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace sva::vk {

class Instance {
 public:
  // validation: enable VK_LAYER_KHRONOS_validation (sva::Error when it is not installed).
  explicit Instance(bool validation);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance handle() const { return instance_; }
  // Validation messages of severity warning or error seen so far.
  std::uint32_t validation_messages() const;
  const std::vector<std::string>& validation_log() const { return log_->messages; }

  struct Log {
    mutable std::mutex mutex;
    std::vector<std::string> messages;
  };

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  // The messenger's callback writes here from driver threads: a stable address.
  std::unique_ptr<Log> log_ = std::make_unique<Log>();
};

}  // namespace sva::vk
