#include "backends/vulkan/command_runner.hpp"

#include <algorithm>
#include <stdexcept>

#include "backends/vulkan/device.hpp"
#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/vk_check.hpp"

namespace sva::vk {

KernelTimes kernel_times_since(const KernelTimes& before, const KernelTimes& now) {
  KernelTimes out;
  for (const auto& [name, k] : now) {
    const auto b = before.find(name);
    const KernelTime was = b == before.end() ? KernelTime{} : b->second;
    if (k.dispatches > was.dispatches) out[name] = {k.ms - was.ms, k.dispatches - was.dispatches};
  }
  return out;
}

std::vector<Dispatch> side_by_side(std::vector<std::vector<Dispatch>> lists) {
  std::vector<Dispatch> out;
  std::size_t rounds = 0, total = 0;
  for (const std::vector<Dispatch>& l : lists) rounds = std::max(rounds, l.size()), total += l.size();
  out.reserve(total);
  for (std::size_t r = 0; r < rounds; ++r) {
    const std::size_t first = out.size();
    for (std::vector<Dispatch>& l : lists) {
      if (r >= l.size()) continue;
      out.push_back(std::move(l[r]));
      out.back().barrier = out.size() - 1 == first;
    }
  }
  return out;
}

CommandRunner::CommandRunner(const Device& device, bool serial, bool timestamps)
    : device_(device), serial_(serial), timestamps_(timestamps) {
  VkCommandPoolCreateInfo cpi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  cpi.queueFamilyIndex = device.queue_family();
  check(vkCreateCommandPool(device.handle(), &cpi, nullptr, &command_pool_), "vkCreateCommandPool");
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  const VkResult r = vkCreateFence(device.handle(), &fci, nullptr, &fence_);
  if (r != VK_SUCCESS) vkDestroyCommandPool(device.handle(), command_pool_, nullptr);
  check(r, "vkCreateFence");
}

CommandRunner::~CommandRunner() {
  const VkDevice dev = device_.handle();
  vkDeviceWaitIdle(dev);
  if (descriptor_pool_) vkDestroyDescriptorPool(dev, descriptor_pool_, nullptr);
  if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
  if (fence_) vkDestroyFence(dev, fence_, nullptr);
  if (command_pool_) vkDestroyCommandPool(dev, command_pool_, nullptr);
}

void CommandRunner::run(const std::vector<Dispatch>& dispatches, std::vector<double>* kernel_ms,
                        const std::vector<Fill>& fills, const std::vector<Copy>& reads) {
  if (dispatches.empty() && fills.empty() && reads.empty()) return;
  const auto started = std::chrono::steady_clock::now();
  const bool timing = kernel_ms && timestamps_ && device_.info().timestamps && !dispatches.empty();
  if (kernel_ms) kernel_ms->clear();
  // Two per dispatch, then the run's first and last command.
  const auto n_queries = static_cast<std::uint32_t>(2 * dispatches.size() + 2);
  if (timing) ensure_queries(n_queries);
  reset_descriptor_pool(dispatches);

  VkCommandBuffer cmd = begin();
  try {
    if (timing) {
      vkCmdResetQueryPool(cmd, queries_, 0, n_queries);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, n_queries - 2);
    }
    record_fills(cmd, fills);
    for (std::uint32_t i = 0; i < dispatches.size(); ++i) record_dispatch(cmd, dispatches[i], i, timing);
    // Make shader writes visible to the host's mapped reads.
    VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &hb, 0, nullptr,
                         0, nullptr);
    record_copies(cmd, reads);
    if (timing) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, n_queries - 1);
  } catch (...) {
    vkFreeCommandBuffers(device_.handle(), command_pool_, 1, &cmd);
    throw;
  }
  end_submit_free(cmd, started);
  if (timing) read_kernel_ms(dispatches, *kernel_ms);
}

VkCommandBuffer CommandRunner::begin() {
  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = command_pool_;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_.handle(), &cai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  cbi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const VkResult r = vkBeginCommandBuffer(cmd, &cbi);
  if (r != VK_SUCCESS) vkFreeCommandBuffers(device_.handle(), command_pool_, 1, &cmd);
  check(r, "vkBeginCommandBuffer");
  return cmd;
}

void CommandRunner::end_submit_free(VkCommandBuffer cmd, std::chrono::steady_clock::time_point started) {
  using ms = std::chrono::duration<double, std::milli>;
  try {
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    const auto submitted = std::chrono::steady_clock::now();
    times_.record_ms += ms(submitted - started).count();
    submit_and_wait(cmd);
    times_.wait_ms += ms(std::chrono::steady_clock::now() - submitted).count();
  } catch (...) {
    vkFreeCommandBuffers(device_.handle(), command_pool_, 1, &cmd);
    throw;
  }
  vkFreeCommandBuffers(device_.handle(), command_pool_, 1, &cmd);
}

void CommandRunner::copy(const std::vector<Copy>& copies) {
  if (copies.empty()) return;
  const auto started = std::chrono::steady_clock::now();
  VkCommandBuffer cmd = begin();
  try {
    record_copies(cmd, copies);
  } catch (...) {
    vkFreeCommandBuffers(device_.handle(), command_pool_, 1, &cmd);
    throw;
  }
  end_submit_free(cmd, started);
}

void CommandRunner::record_copies(VkCommandBuffer cmd, const std::vector<Copy>& copies) const {
  if (copies.empty()) return;
  for (const Copy& c : copies)
    if (c.src_offset + c.bytes > c.src->size() || c.dst_offset + c.bytes > c.dst->size())
      throw std::logic_error("Copy: range not in the buffers");
  // Earlier kernels' writes (a download) are complete before the copy reads them.
  VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr,
                         VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT,
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
  for (const Copy& c : copies) {
    if (c.bytes == 0) continue;
    const VkBufferCopy region{c.src_offset, c.dst_offset, c.bytes};
    vkCmdCopyBuffer(cmd, c.src->handle(), c.dst->handle(), 1, &region);
  }
  VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &after, 0, nullptr, 0,
                       nullptr);
}

void CommandRunner::ensure_queries(std::uint32_t count) {
  if (query_capacity_ >= count) return;
  if (queries_) vkDestroyQueryPool(device_.handle(), queries_, nullptr);
  queries_ = VK_NULL_HANDLE;
  query_capacity_ = 0;
  VkQueryPoolCreateInfo qpi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qpi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qpi.queryCount = count;
  check(vkCreateQueryPool(device_.handle(), &qpi, nullptr, &queries_), "vkCreateQueryPool");
  query_capacity_ = count;
}

// One descriptor set per dispatch; the pool is remade for every run, so the
// sets of the last run are freed with it.
void CommandRunner::reset_descriptor_pool(const std::vector<Dispatch>& dispatches) {
  if (descriptor_pool_) {
    vkDestroyDescriptorPool(device_.handle(), descriptor_pool_, nullptr);
    descriptor_pool_ = VK_NULL_HANDLE;
  }
  std::uint32_t total_bindings = 0;
  for (const auto& d : dispatches) total_bindings += std::max(1u, d.pipeline->bindings());
  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max<std::uint32_t>(total_bindings, 1)};
  VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpi.maxSets = std::max<std::uint32_t>(static_cast<std::uint32_t>(dispatches.size()), 1);
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &ps;
  check(vkCreateDescriptorPool(device_.handle(), &dpi, nullptr, &descriptor_pool_), "vkCreateDescriptorPool");
}

void CommandRunner::record_fills(VkCommandBuffer cmd, const std::vector<Fill>& fills) const {
  for (const Fill& f : fills) {
    const std::size_t bytes = f.bytes ? f.bytes : f.buffer->size() - f.offset;
    if (f.offset % 4 || bytes % 4 || f.offset + bytes > f.buffer->size())
      throw std::logic_error("Fill: range not in the buffer or not 4-byte aligned");
    vkCmdFillBuffer(cmd, f.buffer->handle(), f.offset, bytes, f.value);
  }
  if (fills.empty()) return;
  VkMemoryBarrier fb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &fb, 0, nullptr, 0,
                       nullptr);
}

VkDescriptorSet CommandRunner::bind_buffers(const Dispatch& d) {
  const Pipeline& p = *d.pipeline;
  const VkDescriptorSetLayout layout = p.set_layout();
  VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  dai.descriptorPool = descriptor_pool_;
  dai.descriptorSetCount = 1;
  dai.pSetLayouts = &layout;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(device_.handle(), &dai, &set), "vkAllocateDescriptorSets");
  std::vector<VkDescriptorBufferInfo> infos(p.bindings());
  std::vector<VkWriteDescriptorSet> writes(p.bindings());
  for (std::uint32_t i = 0; i < p.bindings(); ++i) {
    if (d.buffers[i]->size() > device_.info().max_storage_buffer_range)
      throw std::logic_error("Dispatch: a binding exceeds maxStorageBufferRange; the caller must chunk it");
    infos[i] = {d.buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, set,       i,      0, 1,
                 VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,      nullptr, &infos[i], nullptr};
  }
  vkUpdateDescriptorSets(device_.handle(), p.bindings(), writes.data(), 0, nullptr);
  return set;
}

void CommandRunner::record_dispatch(VkCommandBuffer cmd, const Dispatch& d, std::uint32_t index, bool timing) {
  const Pipeline& p = *d.pipeline;
  if (d.buffers.size() != p.bindings()) throw std::logic_error("Dispatch: buffer count does not match the pipeline");
  if (d.push.size() != p.push_bytes())
    throw std::logic_error("Dispatch: push-constant size does not match the pipeline");
  if (d.groups_x > device_.info().max_workgroup_count_x || d.groups_y > device_.info().max_workgroup_count_y)
    throw std::logic_error("Dispatch: too many workgroups");
  const VkDescriptorSet set = bind_buffers(d);
  if (index > 0 && (d.barrier || serial_)) {
    ++barriers_;
    // Earlier writes are visible to this dispatch's shader and, for indirect
    // dispatches, to the read of its workgroup counts.
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr,
                       VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &mb, 0,
                         nullptr, 0, nullptr);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
  if (p.push_bytes())
    vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, p.push_bytes(), d.push.data());
  if (timing) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 2 * index);
  if (d.indirect)
    vkCmdDispatchIndirect(cmd, d.indirect->handle(), 0);
  else if (d.groups_x && d.groups_y)
    vkCmdDispatch(cmd, d.groups_x, d.groups_y, 1);
  if (timing) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 2 * index + 1);
}

void CommandRunner::submit_and_wait(VkCommandBuffer cmd) {
  ++submissions_;
  if (device_.lost()) fail(VK_ERROR_DEVICE_LOST, "vkQueueSubmit (the device was lost by an earlier submission)");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  try {
    check(vkResetFences(device_.handle(), 1, &fence_), "vkResetFences");
    // The injected loss (backends/vulkan/faults.hpp) stands in for the submission, as a reset GPU would answer it.
    check(faults::take_device_loss() ? VK_ERROR_DEVICE_LOST : vkQueueSubmit(device_.queue(), 1, &si, fence_),
          "vkQueueSubmit");
    check(vkWaitForFences(device_.handle(), 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  } catch (const DeviceLost&) {
    device_.mark_lost();
    throw;
  }
}

void CommandRunner::read_kernel_ms(const std::vector<Dispatch>& dispatches, std::vector<double>& kernel_ms) {
  const auto n_queries = static_cast<std::uint32_t>(2 * dispatches.size() + 2);
  std::vector<std::uint64_t> ticks(n_queries);
  check(vkGetQueryPoolResults(device_.handle(), queries_, 0, n_queries, ticks.size() * sizeof(std::uint64_t),
                              ticks.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  kernel_ms.clear();
  for (std::size_t i = 0; i < dispatches.size(); ++i) {
    kernel_ms.push_back(static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * device_.info().timestamp_period_ns *
                        1e-6);
    const Dispatch& d = dispatches[i];
    KernelTime& k = times_.kernels[d.pass ? d.pipeline->name() + ":" + d.pass : d.pipeline->name()];
    k.ms += kernel_ms.back();
    ++k.dispatches;
  }
  times_.span_ms +=
      static_cast<double>(ticks[n_queries - 1] - ticks[n_queries - 2]) * device_.info().timestamp_period_ns * 1e-6;
}

}  // namespace sva::vk
