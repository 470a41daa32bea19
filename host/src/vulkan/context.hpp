#pragma once
// A small Vulkan compute context: instance, device selection, host-visible
// storage buffers, compute pipelines from embedded SPIR-V, and recorded
// sequences of dispatches. Everything the GPU backend needs and nothing more.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sva::vk {

struct ContextOptions {
  std::string device;       // "" = prefer a discrete GPU; else an index or a substring of the device name (env SVA_VK_DEVICE)
  bool validation = false;  // enable VK_LAYER_KHRONOS_validation if present (env SVA_VK_VALIDATION=1)
};

struct DeviceInfo {
  std::string name;
  std::string type;  // "discrete", "integrated", "cpu", ...
  std::uint64_t max_storage_buffer_range = 0;
  std::uint32_t max_workgroup_count_x = 0;
  std::uint32_t max_workgroup_count_y = 0;
  std::uint64_t max_allocation = 0;  // maxMemoryAllocationSize
  bool timestamps = false;        // per-dispatch GPU timing available
  double timestamp_period_ns = 0;
};

class Context;

struct Grid {
  std::uint32_t x = 1, y = 1;
};

class Buffer {
 public:
  Buffer() = default;
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
  friend class Context;
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  std::size_t size_ = 0;
  VkDeviceAddress address_ = 0;
  bool device_local_ = false;
  void release();
};

class Pipeline {
 public:
  Pipeline() = default;
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;
  Pipeline(const Pipeline&) = delete;
  ~Pipeline();
  std::uint32_t bindings() const { return bindings_; }

 private:
  friend class Context;
  VkDevice device_ = VK_NULL_HANDLE;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  std::uint32_t bindings_ = 0;
  std::uint32_t push_bytes_ = 0;
  void release();
};

// A fill of a buffer range with a 32-bit pattern, recorded before a run's
// dispatches: clearing large device tables costs the host nothing.
struct Fill {
  Buffer* buffer;
  std::uint32_t value = 0;
  std::size_t offset = 0;
  std::size_t bytes = 0;  // 0 = to the end of the buffer
};

// One dispatch of a recorded sequence; consecutive dispatches are separated by
// a full compute->compute memory barrier.
struct Dispatch {
  const Pipeline* pipeline;
  std::vector<Buffer*> buffers;      // one per binding, in binding order
  std::vector<std::uint8_t> push;    // push-constant bytes
  std::uint32_t groups_x = 1;
  std::uint32_t groups_y = 1;
  // When set, the workgroup counts come from this buffer (VkDispatchIndirectCommand
  // at offset 0), written by an earlier dispatch of the same run.
  Buffer* indirect = nullptr;
};

class Context {
 public:
  explicit Context(const ContextOptions& options = from_environment());
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  static ContextOptions from_environment();
  const DeviceInfo& info() const { return info_; }
  // Validation messages of severity warning or error seen so far.
  std::uint32_t validation_messages() const;
  const std::vector<std::string>& validation_log() const;

  Buffer create_buffer(std::size_t bytes);
  // A 2-D grid of SVA_WORKGROUP_SIZE-wide workgroups covering `invocations`
  // (x is capped at maxComputeWorkGroupCount[0]); shaders flatten it back.
  Grid grid(std::uint64_t invocations) const;
  Pipeline create_pipeline(std::span<const std::uint32_t> spirv, std::uint32_t bindings, std::uint32_t push_bytes);
  // Records the fills, then the dispatches, into one command buffer, submits
  // and waits. When `kernel_ms` is given and the device supports timestamps,
  // it receives the GPU time of each dispatch (for "where does the time go").
  void run(const std::vector<Dispatch>& dispatches, std::vector<double>* kernel_ms = nullptr,
           const std::vector<Fill>& fills = {});

  struct State;

 private:
  std::unique_ptr<State> s_;
  DeviceInfo info_;
};

}  // namespace sva::vk
