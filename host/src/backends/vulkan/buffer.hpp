#pragma once
// A storage buffer with its memory (a range of the device's memory pool, backends/vulkan/memory_pool.hpp),
// reachable by device address. Two kinds:
//  - mapped: host-visible coherent memory, mapped for its whole life; inputs
//    are written and results read in place (the device's own memory where it
//    has such, else host memory);
//  - device: the device's own memory for what only kernels touch (the map, the
//    vote and belief tables), so that a GPU without a large BAR does not read
//    them over the bus. It is mapped only when that memory happens to be
//    host-visible (lavapipe, integrated GPUs, large BAR) and staging is not
//    forced; else the Context uploads and downloads through staging copies.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "backends/vulkan/memory_pool.hpp"

namespace sva::vk {

class Device;

enum class Memory { mapped, device, readback };
// What a new buffer holds: zeros, or whatever the memory held (for a caller that fills every byte in its own
// submission before a kernel reads it: a belief's new table, cleared beside its rehash).
enum class Contents { zero, undefined };

// The memory types a buffer of `kind` tries, best first, among `allowed` (buffer.cpp says why; a test checks
// the choice on the memory types of a discrete GPU without one).
std::vector<std::uint32_t> memory_types(const VkPhysicalDeviceMemoryProperties& memory, std::uint32_t allowed,
                                        Memory kind, bool discrete);

class Buffer {
 public:
  Buffer() = default;
  // Zero-filled when mapped, unless `contents` is undefined (a device buffer is zeroed by
  // Context::create_device_buffer); `bytes` 0 gives a small placeholder (a binding cannot be empty). `never_map`
  // keeps a device buffer unmapped even in host-visible memory (tests of the staging path).
  Buffer(const Device& device, std::size_t bytes, Memory kind = Memory::mapped, bool never_map = false,
         Contents contents = Contents::zero);
  Buffer(Buffer&&) noexcept;
  Buffer& operator=(Buffer&&) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  ~Buffer();
  std::size_t size() const { return size_; }
  bool mapped() const { return mapped_ != nullptr; }
  // The mapped memory; nullptr for an unmapped device buffer (use Context::upload / download).
  void* data() { return mapped_; }
  const void* data() const { return mapped_; }
  template <class T>
  T* as() {
    return static_cast<T*>(mapped_);
  }
  template <class T>
  const T* as() const {
    return static_cast<const T*>(mapped_);
  }
  VkBuffer handle() const { return buffer_; }
  // For shaders that reach the buffer through GL_EXT_buffer_reference.
  VkDeviceAddress device_address() const { return address_; }
  // Whether the memory is the device's own (device-local and host-mapped, as
  // on lavapipe, integrated GPUs and discrete GPUs with a large BAR) rather
  // than host memory the device reaches over the bus.
  bool device_local() const { return device_local_; }

 private:
  void allocate(const Device& device, Memory kind, bool never_map, Contents contents);
  void release();

  const Device* owner_ = nullptr;  // counts the device memory this buffer holds
  std::size_t counted_ = 0;
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  MemoryPool* pool_ = nullptr;  // the device's, from which range_ came
  MemoryRange range_;
  void* mapped_ = nullptr;
  std::size_t size_ = 0;
  VkDeviceAddress address_ = 0;
  bool device_local_ = false;
};

}  // namespace sva::vk
