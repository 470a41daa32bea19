#pragma once
// Command recording and submission: a run records buffer fills and a sequence
// of compute dispatches into one command buffer, submits it to the device's
// queue and waits. Owns the command pool, the fence, the descriptor pool (one
// set per dispatch, remade each run) and the timestamp queries.
#include <vulkan/vulkan.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "backends/vulkan/buffer.hpp"
#include "backends/vulkan/pipeline.hpp"

namespace sva::vk {

class Device;

// A fill of a buffer range with a 32-bit pattern, recorded before a run's
// dispatches: clearing large device tables costs the host nothing.
struct Fill {
  Buffer* buffer;
  std::uint32_t value = 0;
  std::size_t offset = 0;
  std::size_t bytes = 0;  // 0 = to the end of the buffer
};

// A copy between buffers (staged uploads and downloads of device buffers).
struct Copy {
  const Buffer* src;
  Buffer* dst;
  std::size_t src_offset = 0;
  std::size_t dst_offset = 0;
  std::size_t bytes = 0;
};

// One dispatch of a recorded sequence; consecutive dispatches are separated by
// a full compute->compute memory barrier, unless the later one runs beside it (barrier false: side_by_side).
struct Dispatch {
  const Pipeline* pipeline;
  std::vector<Buffer*> buffers;    // one per binding, in binding order
  std::vector<std::uint8_t> push;  // push-constant bytes
  std::uint32_t groups_x = 1;
  std::uint32_t groups_y = 1;
  // When set, the workgroup counts come from this buffer (VkDispatchIndirectCommand
  // at offset 0), written by an earlier dispatch of the same run.
  Buffer* indirect = nullptr;
  // Which pass of a pipeline that runs several (chosen by a push constant, e.g. belief_reduce's MASS): the device's
  // time by kernel counts it as "pipeline:pass" (a batch's fold column is mostly the belief passes read ahead).
  const char* pass = nullptr;
  // A full barrier before it: it sees every earlier dispatch's writes. false: it touches nothing that the dispatches
  // since the last barrier write or read, and may run beside them (another session's passes: side_by_side).
  bool barrier = true;
};

// Several sessions' lists of dispatches, each list in its own order, recorded round by round: the i-th dispatch of
// every list side by side, one barrier before each round. A list's dispatches keep their order and their barriers
// (consecutive ones are in consecutive rounds); lists must touch disjoint buffers (each session's own belief). On a
// GPU a batch's 64 sessions' belief passes then fill the device together, where one barrier after each of them let
// one small pass at a time run (the seventh GPU run: the fold column, 54 ms of a 64-session submission).
std::vector<Dispatch> side_by_side(std::vector<std::vector<Dispatch>> lists);

// One pipeline's timed dispatches, summed: their GPU time and how many ran.
struct KernelTime {
  double ms = 0.0;
  std::uint64_t dispatches = 0;
};
// The device's time by kernel: KernelTime per pipeline name (Pipeline::name, the shader's file stem).
using KernelTimes = std::map<std::string, KernelTime>;
// What `now` adds to `before` (a caller's window on a runner's running sums); names with no dispatch in it are left
// out.
KernelTimes kernel_times_since(const KernelTimes& before, const KernelTimes& now);

// Where the submissions' time went, summed over them: the host recording each (descriptor sets, commands), the wait
// from its submission until its fence (the device's work and the latency around it), and the device's span from its
// first command to its last, where the device has timestamps (in runs whose kernels are timed; 0 elsewhere). A
// batch's host time on a GPU is what the kernels' own times leave (docs/vulkan-backend.md): this says which part.
struct SubmitTimes {
  double record_ms = 0.0;
  double wait_ms = 0.0;
  double span_ms = 0.0;
  // The timed dispatches by pipeline: which kernels the kernels' time is (a fold's passes, the votes, a table's
  // growth). Summed over the names, every run's kernel_ms.
  KernelTimes kernels;
};

class CommandRunner {
 public:
  // serial: a barrier before every dispatch, side_by_side's rounds ignored (env SVA_VK_SERIAL=1, to compare);
  // timestamps false: no run is timed, whatever it asks (env SVA_VK_TIMESTAMPS=0).
  explicit CommandRunner(const Device& device, bool serial = false, bool timestamps = true);
  ~CommandRunner();
  CommandRunner(const CommandRunner&) = delete;
  CommandRunner& operator=(const CommandRunner&) = delete;

  // Records the fills, then the dispatches, then the `reads` (copies of what the dispatches wrote into buffers the
  // host reads), submits and waits. When `kernel_ms` is given and the device supports timestamps, it receives the
  // GPU time of each dispatch (for "where does the time go").
  void run(const std::vector<Dispatch>& dispatches, std::vector<double>* kernel_ms = nullptr,
           const std::vector<Fill>& fills = {}, const std::vector<Copy>& reads = {});
  // Records the copies, submits and waits; their writes are visible to later
  // runs and to the host's mapped reads.
  void copy(const std::vector<Copy>& copies);
  // Submissions so far (each a round trip: submit, then wait for the fence): what a batch's reads save.
  std::uint64_t submissions() const { return submissions_; }
  const SubmitTimes& times() const { return times_; }
  // Starts the sums of times() again (a benchmark's own window; the backends take differences instead, as a shared
  // engine's runner serves several).
  void reset_times() { times_ = {}; }
  // Barriers recorded between dispatches so far: what side_by_side saves.
  std::uint64_t barriers() const { return barriers_; }

 private:
  VkCommandBuffer begin();
  // Ends, submits and waits for cmd, recorded since `started` (its host time), then frees it.
  void end_submit_free(VkCommandBuffer cmd, std::chrono::steady_clock::time_point started);
  void ensure_queries(std::uint32_t count);
  void reset_descriptor_pool(const std::vector<Dispatch>& dispatches);
  VkDescriptorSet bind_buffers(const Dispatch& d);
  void record_fills(VkCommandBuffer cmd, const std::vector<Fill>& fills) const;
  void record_copies(VkCommandBuffer cmd, const std::vector<Copy>& copies) const;
  void record_dispatch(VkCommandBuffer cmd, const Dispatch& d, std::uint32_t index, bool timing);
  void submit_and_wait(VkCommandBuffer cmd);
  // The dispatches' times, and into times_ the run's span (its queries past theirs) and each one's time under its
  // pipeline's name.
  void read_kernel_ms(const std::vector<Dispatch>& dispatches, std::vector<double>& kernel_ms);

  const Device& device_;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::uint32_t query_capacity_ = 0;
  std::uint64_t submissions_ = 0;  // the Context's lock orders every run and copy
  std::uint64_t barriers_ = 0;
  bool serial_ = false;
  bool timestamps_ = true;
  SubmitTimes times_;
};

}  // namespace sva::vk
