#pragma once
// A small Vulkan compute context: the facade the kernel launchers use. It owns
// one RAII piece per Vulkan object kind, each in its own file:
//   backends/vulkan/instance.hpp        the instance and the validation log
//   backends/vulkan/device.hpp          device selection (feature queries), limits, the queue
//   backends/vulkan/buffer.hpp          host-mapped storage buffers with device addresses
//   backends/vulkan/pipeline.hpp        compute pipelines and their descriptor-set layouts
//   backends/vulkan/command_runner.hpp  recorded fills and dispatches, submitted and waited for
// Everything the GPU backend needs and nothing more.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "backends/vulkan/buffer.hpp"
#include "backends/vulkan/command_runner.hpp"
#include "backends/vulkan/device.hpp"
#include "backends/vulkan/instance.hpp"
#include "backends/vulkan/pipeline.hpp"

namespace sva::vk {

struct ContextOptions {
  // "" = prefer a discrete GPU; else an index or a substring of the device name (env SVA_VK_DEVICE)
  std::string device;
  bool validation = false;  // enable VK_LAYER_KHRONOS_validation if present (env SVA_VK_VALIDATION=1)
  // Keep device buffers unmapped and stage every upload and download, as on a
  // GPU without a large BAR (env SVA_VK_STAGING=1): tests the staging path on lavapipe.
  bool force_staging = false;
  // A barrier before every dispatch, as before sessions' passes ran side by side (env SVA_VK_SERIAL=1): a device run
  // compares the two (vk::side_by_side).
  bool serial_dispatches = false;
  // Timestamps around each dispatch where a caller asks for its kernels' times (env SVA_VK_TIMESTAMPS=0: none, so
  // that a device run measures the wall time of dispatches side by side without a timestamp between them).
  bool timestamps = true;
};

class Context {
 public:
  explicit Context(const ContextOptions& options = from_environment());
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  static ContextOptions from_environment();
  const DeviceInfo& info() const { return device_.info(); }
  // Validation messages of severity warning or error seen so far.
  std::uint32_t validation_messages() const { return instance_.validation_messages(); }
  const std::vector<std::string>& validation_log() const { return instance_.validation_log(); }

  // A host-mapped buffer: the kernels' inputs and outputs.
  Buffer create_buffer(std::size_t bytes) { return Buffer(device_, bytes, Memory::mapped); }
  // A buffer in the device's own memory, zero-filled: what only kernels touch.
  Buffer create_device_buffer(std::size_t bytes);
  // The same, its contents undefined: for a caller that fills every byte in its own submission before a kernel
  // reads it (zeroing it first cost a submission and a wait on a GPU, a memset of the whole buffer where it is mapped).
  Buffer create_uncleared_device_buffer(std::size_t bytes) {
    return Buffer(device_, bytes, Memory::device, force_staging_, Contents::undefined);
  }
  // Host data into a buffer and back: in place when it is mapped, else through
  // a staging buffer and a copy on the device.
  void upload(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset = 0);
  void download(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset = 0);
  // A 2-D grid of SVA_WORKGROUP_SIZE-wide workgroups covering `invocations`
  // (x is capped at maxComputeWorkGroupCount[0]); shaders flatten it back.
  Grid grid(std::uint64_t invocations) const { return device_.grid(invocations); }
  // `name`: the shader's file stem, what its dispatches' time is summed under (SubmitTimes::kernels).
  Pipeline create_pipeline(std::string name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                           std::uint32_t push_bytes) {
    return Pipeline(device_, std::move(name), spirv, bindings, push_bytes);
  }
  // Records the fills, then the dispatches, then the `reads` (copies of their results into readback buffers, so that
  // a result comes back in the submission that computed it, not in a staged download of its own), into one command
  // buffer, submits and waits. When `kernel_ms` is given and the device supports timestamps, it receives the GPU
  // time of each dispatch (for "where does the time go"). Thread-safe: runs of several users of one context
  // (recognizers sharing a VulkanEngine) take turns on its queue.
  void run(const std::vector<Dispatch>& dispatches, std::vector<double>* kernel_ms = nullptr,
           const std::vector<Fill>& fills = {}, const std::vector<Copy>& reads = {}) {
    std::lock_guard lock(mutex_);
    commands_.run(dispatches, kernel_ms, fills, reads);
  }
  // A host-mapped buffer in memory the host reads fast (cached where the device offers it): where a run's `reads`
  // put the results of kernels that write device memory.
  Buffer create_readback_buffer(std::size_t bytes) { return Buffer(device_, bytes, Memory::readback); }
  bool force_staging() const { return force_staging_; }
  // Whether the host reads what kernels wrote into mapped buffers from host-cached copies made at the end of the
  // submission (gpu::add_mirror_read): on a discrete GPU a mapped buffer is the device's memory behind its PCI BAR,
  // which the host reads uncached, one bus round trip per load; and where staging is forced, so that lavapipe's tests
  // take that path too. Elsewhere (lavapipe, integrated GPUs) mapped memory is the host's own: read in place.
  bool reads_through_copies() const { return info().type == "discrete" || force_staging_; }
  // Submissions so far, runs and staged transfers alike (each a round trip to the device).
  std::uint64_t submissions() {
    std::lock_guard lock(mutex_);
    return commands_.submissions();
  }
  // Barriers recorded between dispatches so far (CommandRunner::barriers).
  std::uint64_t barriers() {
    std::lock_guard lock(mutex_);
    return commands_.barriers();
  }

  // Where the submissions' time went so far (CommandRunner's SubmitTimes), the device's time by kernel included.
  SubmitTimes submit_times() {
    std::lock_guard lock(mutex_);
    return commands_.times();
  }
  // Starts those sums again (CommandRunner::reset_times).
  void reset_submit_times() {
    std::lock_guard lock(mutex_);
    commands_.reset_times();
  }
  // Memory allocations so far (vkAllocateMemory: the pool's blocks and large buffers' own), and buffers made.
  std::uint64_t allocations() const { return device_.allocations(); }
  std::uint64_t buffers_made() const { return device_.buffers_made(); }

  const Instance& instance() const { return instance_; }
  const Device& device() const { return device_; }

 private:
  // Declaration order is destruction order reversed: commands, device, instance.
  Instance instance_;
  Device device_;
  CommandRunner commands_;
  // The staging buffer of an upload() or download() of `bytes` (unmapped destinations): `kept` (up to 1 MiB,
  // kept between small transfers) or, for a large one, `temporary`, made for the call.
  Buffer& staging_for(Buffer& kept, Buffer& temporary, Memory kind, std::size_t bytes);
  Buffer upload_staging_, readback_staging_;
  bool force_staging_ = false;
  std::mutex mutex_;
};

}  // namespace sva::vk
