#pragma once
// The compute device: the physical device picked among those the engine can
// use (a compute queue, Vulkan 1.2, 64-bit integers and buffer atomics, buffer
// device addresses), its limits, and the logical device with its one queue.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "backends/vulkan/memory_pool.hpp"

namespace sva::vk {

class Instance;

struct DeviceInfo {
  std::string name;
  std::string type;  // "discrete", "integrated", "cpu", ...
  std::uint64_t max_storage_buffer_range = 0;
  std::uint32_t max_workgroup_count_x = 0;
  std::uint32_t max_workgroup_count_y = 0;
  std::uint64_t max_allocation = 0;   // maxMemoryAllocationSize
  std::uint32_t max_allocations = 0;  // maxMemoryAllocationCount: allocations live at once (4096 on many drivers)
  bool timestamps = false;            // per-dispatch GPU timing available
  std::uint32_t subgroup_size = 0;
  // Basic, vote, ballot and arithmetic subgroup operations in compute shaders: the
  // vote kernel pre-aggregates equal keys across a subgroup before its atomics.
  bool subgroup_aggregation = false;
  double timestamp_period_ns = 0;
  std::uint64_t device_local_bytes = 0;  // the largest device-local memory heap (what sizes a batch's submissions)
};

struct Grid {
  std::uint32_t x = 1, y = 1;
};

class Device {
 public:
  // choice: "" = prefer a discrete GPU; else an index among the usable devices
  // or a substring of the device name. sva::Error says why none is usable.
  Device(const Instance& instance, const std::string& choice);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkDevice handle() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const DeviceInfo& info() const { return info_; }
  const VkPhysicalDeviceMemoryProperties& memory() const { return memory_; }
  // Bytes of device memory (the device's own heaps) held by live buffers, and
  // the most held at once: what a run costs the GPU.
  std::uint64_t device_bytes() const { return device_bytes_.load(); }
  std::uint64_t peak_device_bytes() const { return peak_device_bytes_.load(); }
  void count_device_bytes(std::int64_t delta) const;
  // Memory allocations made so far (vkAllocateMemory: a block of the pool, or a large buffer's own): on a GPU each
  // is a call into the driver's kernel side, which `sva bench` counts per update beside the submissions.
  std::uint64_t allocations() const { return pool_->allocations(); }
  // Buffers made so far, each a range of the pool or an allocation of its own.
  std::uint64_t buffers_made() const { return buffers_made_.load(); }
  void count_buffer() const { buffers_made_.fetch_add(1); }
  // Where every buffer's memory comes from (backends/vulkan/memory_pool.hpp).
  MemoryPool& pool() const { return *pool_; }
  // A 2-D grid of SVA_WORKGROUP_SIZE-wide workgroups covering `invocations`
  // (x is capped at maxComputeWorkGroupCount[0]); shaders flatten it back.
  Grid grid(std::uint64_t invocations) const;
  // Set once a submission returned VK_ERROR_DEVICE_LOST: every later use throws sva::DeviceLost at once (the
  // driver would too), and no new engine is made on this device (VulkanEngine::shared).
  bool lost() const { return lost_.load(); }
  void mark_lost() const { lost_ = true; }

 private:
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  DeviceInfo info_;
  VkPhysicalDeviceMemoryProperties memory_{};
  mutable std::atomic<std::uint64_t> device_bytes_{0}, peak_device_bytes_{0}, buffers_made_{0};
  std::unique_ptr<MemoryPool> pool_;  // freed before the device
  mutable std::atomic<bool> lost_{false};
};

}  // namespace sva::vk
