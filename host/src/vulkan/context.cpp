#include "vulkan/context.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "sva_shared.h"  // SVA_WORKGROUP_SIZE

namespace sva::vk {

namespace {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw Error(std::string("Vulkan: ") + what + " failed (VkResult " + std::to_string(r) + ")");
}

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

}  // namespace

struct Context::State {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkQueryPool queries = VK_NULL_HANDLE;
  std::uint32_t query_capacity = 0;
  VkPhysicalDeviceMemoryProperties memory{};
  std::mutex log_mutex;
  std::vector<std::string> log;
};

namespace {
VKAPI_ATTR VkBool32 VKAPI_CALL on_validation(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    auto* s = static_cast<Context::State*>(user);
    std::lock_guard lock(s->log_mutex);
    s->log.emplace_back(data && data->pMessage ? data->pMessage : "(no message)");
  }
  return VK_FALSE;
}
}  // namespace

ContextOptions Context::from_environment() {
  ContextOptions o;
  if (const char* d = std::getenv("SVA_VK_DEVICE")) o.device = d;
  if (const char* v = std::getenv("SVA_VK_VALIDATION")) o.validation = std::string(v) == "1";
  return o;
}

Context::Context(const ContextOptions& options) : s_(std::make_unique<State>()) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "sva";
  app.apiVersion = VK_API_VERSION_1_2;

  std::vector<const char*> layers, extensions;
  if (options.validation) {
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> props(n);
    vkEnumerateInstanceLayerProperties(&n, props.data());
    bool have = std::any_of(props.begin(), props.end(),
                            [](const auto& p) { return std::strcmp(p.layerName, "VK_LAYER_KHRONOS_validation") == 0; });
    if (!have) throw Error("Vulkan validation requested (SVA_VK_VALIDATION=1) but VK_LAYER_KHRONOS_validation is not installed (apt-get install vulkan-validationlayers)");
    layers.push_back("VK_LAYER_KHRONOS_validation");
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = static_cast<std::uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  VkResult r = vkCreateInstance(&ici, nullptr, &s_->instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
    throw Error("no Vulkan device: no Vulkan driver is installed (apt-get install mesa-vulkan-drivers for the lavapipe CPU driver)");
  check(r, "vkCreateInstance");
  if (options.validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(s_->instance, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mci.pfnUserCallback = on_validation;
    mci.pUserData = s_.get();
    if (create) check(create(s_->instance, &mci, nullptr, &s_->messenger), "vkCreateDebugUtilsMessengerEXT");
  }

  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(s_->instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(s_->instance, &count, devices.data());

  // Candidates must have a compute queue, 64-bit integers and 64-bit buffer atomics.
  struct Candidate { VkPhysicalDevice dev; VkPhysicalDeviceProperties props; std::uint32_t family; std::uint32_t timestamp_bits; };
  std::vector<Candidate> ok;
  std::string rejected;
  for (auto dev : devices) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(dev, &props);
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    if (props.apiVersion >= VK_API_VERSION_1_2) f2.pNext = &v12;
    vkGetPhysicalDeviceFeatures2(dev, &f2);
    std::uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(dev, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> qf(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(dev, &nq, qf.data());
    std::uint32_t family = UINT32_MAX;
    for (std::uint32_t i = 0; i < nq; ++i)
      if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) { family = i; break; }
    if (family == UINT32_MAX || !f2.features.shaderInt64 || !v12.shaderBufferInt64Atomics || !v12.bufferDeviceAddress ||
        props.apiVersion < VK_API_VERSION_1_2) {
      rejected += std::string(" ") + props.deviceName + " (lacks compute/int64 atomics/buffer device address/Vulkan 1.2);";
      continue;
    }
    ok.push_back({dev, props, family, qf[family].timestampValidBits});
  }
  if (ok.empty())
    throw Error("no Vulkan device: " + (devices.empty() ? std::string("the loader found no physical device") : "none usable:" + rejected));

  const Candidate* pick = nullptr;
  if (!options.device.empty()) {
    char* end = nullptr;
    long idx = std::strtol(options.device.c_str(), &end, 10);
    if (end && *end == '\0') {
      if (idx < 0 || static_cast<std::size_t>(idx) >= ok.size())
        throw Error("Vulkan device index " + options.device + " out of range (" + std::to_string(ok.size()) + " usable)");
      pick = &ok[static_cast<std::size_t>(idx)];
    } else {
      for (const auto& c : ok)
        if (std::string(c.props.deviceName).find(options.device) != std::string::npos) { pick = &c; break; }
      if (!pick) throw Error("no Vulkan device matches \"" + options.device + "\"");
    }
  } else {
    auto rank = [](VkPhysicalDeviceType t) {
      switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
      }
    };
    pick = &*std::min_element(ok.begin(), ok.end(),
                              [&](const auto& a, const auto& b) { return rank(a.props.deviceType) < rank(b.props.deviceType); });
  }
  s_->physical = pick->dev;
  s_->queue_family = pick->family;
  info_.name = pick->props.deviceName;
  info_.type = type_name(pick->props.deviceType);
  info_.max_storage_buffer_range = pick->props.limits.maxStorageBufferRange;
  info_.max_workgroup_count_x = pick->props.limits.maxComputeWorkGroupCount[0];
  info_.max_workgroup_count_y = pick->props.limits.maxComputeWorkGroupCount[1];
  VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &m3;
  vkGetPhysicalDeviceProperties2(pick->dev, &p2);
  info_.max_allocation = m3.maxMemoryAllocationSize;
  info_.timestamps = pick->timestamp_bits > 0 && pick->props.limits.timestampPeriod > 0;
  info_.timestamp_period_ns = pick->props.limits.timestampPeriod;
  vkGetPhysicalDeviceMemoryProperties(s_->physical, &s_->memory);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = s_->queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // 64-bit atomics for the vote and belief tables; device addresses for the
  // belief tables, which grow past one binding's range (maxStorageBufferRange).
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  v12.shaderBufferInt64Atomics = VK_TRUE;
  v12.bufferDeviceAddress = VK_TRUE;
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &v12;
  f2.features.shaderInt64 = VK_TRUE;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &f2;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  check(vkCreateDevice(s_->physical, &dci, nullptr, &s_->device), "vkCreateDevice");
  vkGetDeviceQueue(s_->device, s_->queue_family, 0, &s_->queue);

  VkCommandPoolCreateInfo cpi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  cpi.queueFamilyIndex = s_->queue_family;
  check(vkCreateCommandPool(s_->device, &cpi, nullptr, &s_->command_pool), "vkCreateCommandPool");
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(s_->device, &fci, nullptr, &s_->fence), "vkCreateFence");
}

Context::~Context() {
  if (!s_) return;
  if (s_->device) {
    vkDeviceWaitIdle(s_->device);
    if (s_->descriptor_pool) vkDestroyDescriptorPool(s_->device, s_->descriptor_pool, nullptr);
    if (s_->queries) vkDestroyQueryPool(s_->device, s_->queries, nullptr);
    if (s_->fence) vkDestroyFence(s_->device, s_->fence, nullptr);
    if (s_->command_pool) vkDestroyCommandPool(s_->device, s_->command_pool, nullptr);
    vkDestroyDevice(s_->device, nullptr);
  }
  if (s_->messenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(s_->instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(s_->instance, s_->messenger, nullptr);
  }
  if (s_->instance) vkDestroyInstance(s_->instance, nullptr);
}

std::uint32_t Context::validation_messages() const {
  std::lock_guard lock(s_->log_mutex);
  return static_cast<std::uint32_t>(s_->log.size());
}
const std::vector<std::string>& Context::validation_log() const { return s_->log; }

Buffer Context::create_buffer(std::size_t bytes) {
  if (bytes == 0) bytes = 16;
  Buffer b;
  b.device_ = s_->device;
  b.size_ = bytes;
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = bytes;
  if (bytes > info_.max_allocation)
    throw Error("Vulkan: a buffer of " + std::to_string(bytes) + " bytes exceeds the device's largest allocation (" +
                std::to_string(info_.max_allocation) + " bytes)");
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
              VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(s_->device, &bci, nullptr, &b.buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(s_->device, b.buffer_, &req);
  // Host-mapped, coherent memory, the device's own where it has such (lavapipe,
  // integrated GPUs, discrete GPUs with a large BAR): the host fills inputs and
  // reads results without staging copies, and the kernels' atomics stay on the
  // device. Otherwise (or when that heap is full) host memory.
  const VkMemoryPropertyFlags mapped = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  std::vector<std::uint32_t> types;
  for (VkMemoryPropertyFlags want : {mapped | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, mapped})
    for (std::uint32_t i = 0; i < s_->memory.memoryTypeCount; ++i)
      if ((req.memoryTypeBits & (1u << i)) && (s_->memory.memoryTypes[i].propertyFlags & want) == want &&
          std::find(types.begin(), types.end(), i) == types.end())
        types.push_back(i);
  if (types.empty()) throw Error("Vulkan: no host-visible coherent memory type");
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.pNext = &flags;
  mai.allocationSize = req.size;
  VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  for (std::uint32_t type : types) {
    mai.memoryTypeIndex = type;
    r = vkAllocateMemory(s_->device, &mai, nullptr, &b.memory_);
    if (r == VK_SUCCESS) {
      b.device_local_ = (s_->memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) != 0;
      break;
    }
    if (r != VK_ERROR_OUT_OF_DEVICE_MEMORY && r != VK_ERROR_OUT_OF_HOST_MEMORY) break;
  }
  if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
    throw Error("Vulkan: out of memory allocating " + std::to_string(bytes) + " bytes");
  check(r, "vkAllocateMemory");
  check(vkBindBufferMemory(s_->device, b.buffer_, b.memory_, 0), "vkBindBufferMemory");
  check(vkMapMemory(s_->device, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_), "vkMapMemory");
  VkBufferDeviceAddressInfo ai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  ai.buffer = b.buffer_;
  b.address_ = vkGetBufferDeviceAddress(s_->device, &ai);
  std::memset(b.mapped_, 0, bytes);
  return b;
}

Grid Context::grid(std::uint64_t invocations) const {
  const std::uint64_t groups = std::max<std::uint64_t>((invocations + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE, 1);
  const std::uint64_t x = std::min<std::uint64_t>(groups, info_.max_workgroup_count_x);
  const std::uint64_t y = (groups + x - 1) / x;
  if (y > info_.max_workgroup_count_y)
    throw Error("Vulkan: " + std::to_string(invocations) + " invocations exceed the device's workgroup grid");
  return {static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)};
}

Pipeline Context::create_pipeline(std::span<const std::uint32_t> spirv, std::uint32_t bindings, std::uint32_t push_bytes) {
  Pipeline p;
  p.device_ = s_->device;
  p.bindings_ = bindings;
  p.push_bytes_ = push_bytes;
  VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = spirv.size_bytes();
  smi.pCode = spirv.data();
  check(vkCreateShaderModule(s_->device, &smi, nullptr, &p.module_), "vkCreateShaderModule");
  std::vector<VkDescriptorSetLayoutBinding> b(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i)
    b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo dli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dli.bindingCount = bindings;
  dli.pBindings = b.data();
  check(vkCreateDescriptorSetLayout(s_->device, &dli, nullptr, &p.set_layout_), "vkCreateDescriptorSetLayout");
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &p.set_layout_;
  pli.pushConstantRangeCount = push_bytes ? 1 : 0;
  pli.pPushConstantRanges = push_bytes ? &range : nullptr;
  check(vkCreatePipelineLayout(s_->device, &pli, nullptr, &p.layout_), "vkCreatePipelineLayout");
  VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, p.module_, "main", nullptr};
  cpi.layout = p.layout_;
  check(vkCreateComputePipelines(s_->device, VK_NULL_HANDLE, 1, &cpi, nullptr, &p.pipeline_), "vkCreateComputePipelines");
  return p;
}

void Context::run(const std::vector<Dispatch>& dispatches, std::vector<double>* kernel_ms, const std::vector<Fill>& fills) {
  if (dispatches.empty() && fills.empty()) return;
  const bool timing = kernel_ms && info_.timestamps && !dispatches.empty();
  if (kernel_ms) kernel_ms->clear();
  const auto n_queries = static_cast<std::uint32_t>(2 * dispatches.size());
  if (timing && s_->query_capacity < n_queries) {
    if (s_->queries) vkDestroyQueryPool(s_->device, s_->queries, nullptr);
    VkQueryPoolCreateInfo qpi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qpi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpi.queryCount = n_queries;
    check(vkCreateQueryPool(s_->device, &qpi, nullptr, &s_->queries), "vkCreateQueryPool");
    s_->query_capacity = n_queries;
  }
  if (s_->descriptor_pool) {
    vkDestroyDescriptorPool(s_->device, s_->descriptor_pool, nullptr);
    s_->descriptor_pool = VK_NULL_HANDLE;
  }
  std::uint32_t total_bindings = 0;
  for (const auto& d : dispatches) total_bindings += std::max(1u, d.pipeline->bindings_);
  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max<std::uint32_t>(total_bindings, 1)};
  VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpi.maxSets = std::max<std::uint32_t>(static_cast<std::uint32_t>(dispatches.size()), 1);
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &ps;
  check(vkCreateDescriptorPool(s_->device, &dpi, nullptr, &s_->descriptor_pool), "vkCreateDescriptorPool");

  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = s_->command_pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(s_->device, &cai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  cbi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &cbi), "vkBeginCommandBuffer");
  if (timing) vkCmdResetQueryPool(cmd, s_->queries, 0, n_queries);
  for (const Fill& f : fills) {
    const std::size_t bytes = f.bytes ? f.bytes : f.buffer->size() - f.offset;
    if (f.offset % 4 || bytes % 4 || f.offset + bytes > f.buffer->size()) throw std::logic_error("Fill: range not in the buffer or not 4-byte aligned");
    vkCmdFillBuffer(cmd, f.buffer->handle(), f.offset, bytes, f.value);
  }
  if (!fills.empty()) {
    VkMemoryBarrier fb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &fb, 0, nullptr, 0, nullptr);
  }
  bool first = true;
  std::uint32_t index = 0;
  for (const auto& d : dispatches) {
    const Pipeline& p = *d.pipeline;
    if (d.buffers.size() != p.bindings_) throw std::logic_error("Dispatch: buffer count does not match the pipeline");
    if (d.push.size() != p.push_bytes_) throw std::logic_error("Dispatch: push-constant size does not match the pipeline");
    if (d.groups_x > info_.max_workgroup_count_x || d.groups_y > info_.max_workgroup_count_y)
      throw std::logic_error("Dispatch: too many workgroups");
    VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    dai.descriptorPool = s_->descriptor_pool;
    dai.descriptorSetCount = 1;
    dai.pSetLayouts = &p.set_layout_;
    VkDescriptorSet set;
    check(vkAllocateDescriptorSets(s_->device, &dai, &set), "vkAllocateDescriptorSets");
    std::vector<VkDescriptorBufferInfo> infos(p.bindings_);
    std::vector<VkWriteDescriptorSet> writes(p.bindings_);
    for (std::uint32_t i = 0; i < p.bindings_; ++i) {
      if (d.buffers[i]->size() > info_.max_storage_buffer_range)
        throw std::logic_error("Dispatch: a binding exceeds maxStorageBufferRange; the caller must chunk it");
      infos[i] = {d.buffers[i]->handle(), 0, VK_WHOLE_SIZE};
      writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, set, i, 0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, nullptr, &infos[i], nullptr};
    }
    vkUpdateDescriptorSets(s_->device, p.bindings_, writes.data(), 0, nullptr);
    if (!first) {
      // Earlier writes are visible to this dispatch's shader and, for indirect
      // dispatches, to the read of its workgroup counts.
      VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                         VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT};
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &mb, 0, nullptr,
                           0, nullptr);
    }
    first = false;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout_, 0, 1, &set, 0, nullptr);
    if (p.push_bytes_) vkCmdPushConstants(cmd, p.layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, p.push_bytes_, d.push.data());
    if (timing) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, s_->queries, 2 * index);
    if (d.indirect) vkCmdDispatchIndirect(cmd, d.indirect->handle(), 0);
    else if (d.groups_x && d.groups_y) vkCmdDispatch(cmd, d.groups_x, d.groups_y, 1);
    if (timing) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, s_->queries, 2 * index + 1);
    ++index;
  }
  // Make shader writes visible to the host's mapped reads.
  VkMemoryBarrier hb{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &hb, 0, nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkResetFences(s_->device, 1, &s_->fence), "vkResetFences");
  check(vkQueueSubmit(s_->queue, 1, &si, s_->fence), "vkQueueSubmit");
  VkResult w = vkWaitForFences(s_->device, 1, &s_->fence, VK_TRUE, UINT64_MAX);
  vkFreeCommandBuffers(s_->device, s_->command_pool, 1, &cmd);
  check(w, "vkWaitForFences");
  if (timing) {
    std::vector<std::uint64_t> ticks(n_queries);
    check(vkGetQueryPoolResults(s_->device, s_->queries, 0, n_queries, ticks.size() * sizeof(std::uint64_t), ticks.data(),
                                sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    kernel_ms->clear();
    for (std::size_t i = 0; i < dispatches.size(); ++i)
      kernel_ms->push_back(static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * info_.timestamp_period_ns * 1e-6);
  }
}

void Buffer::release() {
  if (device_) {
    if (mapped_) vkUnmapMemory(device_, memory_);
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
  }
  device_ = VK_NULL_HANDLE;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = 0;
  address_ = 0;
  device_local_ = false;
}
Buffer::~Buffer() { release(); }
Buffer::Buffer(Buffer&& o) noexcept { *this = std::move(o); }
Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    std::swap(device_, o.device_);
    std::swap(buffer_, o.buffer_);
    std::swap(memory_, o.memory_);
    std::swap(mapped_, o.mapped_);
    std::swap(size_, o.size_);
    std::swap(address_, o.address_);
    std::swap(device_local_, o.device_local_);
  }
  return *this;
}

void Pipeline::release() {
  if (device_) {
    if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    if (module_) vkDestroyShaderModule(device_, module_, nullptr);
  }
  device_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}
Pipeline::~Pipeline() { release(); }
Pipeline::Pipeline(Pipeline&& o) noexcept { *this = std::move(o); }
Pipeline& Pipeline::operator=(Pipeline&& o) noexcept {
  if (this != &o) {
    release();
    std::swap(device_, o.device_);
    std::swap(module_, o.module_);
    std::swap(set_layout_, o.set_layout_);
    std::swap(layout_, o.layout_);
    std::swap(pipeline_, o.pipeline_);
    std::swap(bindings_, o.bindings_);
    std::swap(push_bytes_, o.push_bytes_);
  }
  return *this;
}

}  // namespace sva::vk
