#pragma once
// A storage buffer with its memory, mapped for the host for its whole life and
// reachable by device address: inputs are written and results read in place,
// without staging copies.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>

namespace sva::vk {

class Device;

class Buffer {
 public:
  Buffer() = default;
  // Zero-filled; `bytes` 0 gives a small placeholder (a binding cannot be empty).
  Buffer(const Device& device, std::size_t bytes);
  Buffer(Buffer&&) noexcept;
  Buffer& operator=(Buffer&&) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer();
  std::size_t size() const { return size_; }
  void* data() { return mapped_; }
  const void* data() const { return mapped_; }
  template <class T>
  T* as() { return static_cast<T*>(mapped_); }
  template <class T>
  const T* as() const { return static_cast<const T*>(mapped_); }
  VkBuffer handle() const { return buffer_; }
  // For shaders that reach the buffer through GL_EXT_buffer_reference.
  VkDeviceAddress device_address() const { return address_; }
  // Whether the memory is the device's own (device-local and host-mapped, as
  // on lavapipe, integrated GPUs and discrete GPUs with a large BAR) rather
  // than host memory the device reaches over the bus.
  bool device_local() const { return device_local_; }

 private:
  void allocate(const Device& device);
  void release();

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  std::size_t size_ = 0;
  VkDeviceAddress address_ = 0;
  bool device_local_ = false;
};

}  // namespace sva::vk
