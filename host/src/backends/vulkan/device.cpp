#include "backends/vulkan/device.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/instance.hpp"
#include "backends/vulkan/vk_check.hpp"
#include "sva_shared.h"  // SVA_WORKGROUP_SIZE

namespace sva::vk {

namespace {

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

// Without a choice, the fastest kind of device comes first.
int rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

struct Candidate {
  VkPhysicalDevice dev;
  VkPhysicalDeviceProperties props;
  std::uint32_t family;
  std::uint32_t timestamp_bits;
};

std::uint32_t compute_family(VkPhysicalDevice dev, std::uint32_t* timestamp_bits) {
  std::uint32_t nq = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(dev, &nq, nullptr);
  std::vector<VkQueueFamilyProperties> qf(nq);
  vkGetPhysicalDeviceQueueFamilyProperties(dev, &nq, qf.data());
  for (std::uint32_t i = 0; i < nq; ++i)
    if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      *timestamp_bits = qf[i].timestampValidBits;
      return i;
    }
  return UINT32_MAX;
}

// The feature queries: 64-bit integers and buffer atomics (the vote and belief
// tables), buffer device addresses (belief tables past one binding's range).
// The names of what the device lacks, as the Vulkan specification spells them
// (with the fault injection's forced one, backends/vulkan/faults.hpp); empty when usable.
std::vector<std::string> missing_features(VkPhysicalDevice dev, const VkPhysicalDeviceProperties& props) {
  std::vector<std::string> missing;
  if (props.apiVersion < VK_API_VERSION_1_2) missing.push_back("Vulkan 1.2");
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  if (props.apiVersion >= VK_API_VERSION_1_2) {
    f2.pNext = &v12;
    vkGetPhysicalDeviceFeatures2(dev, &f2);
  }
  const std::string forced = faults::missing_feature();
  const auto need = [&](bool present, const char* name) {
    if ((!present || forced == name) && std::find(missing.begin(), missing.end(), name) == missing.end())
      missing.push_back(name);
  };
  need(f2.features.shaderInt64, "shaderInt64");
  need(v12.shaderBufferInt64Atomics, "shaderBufferInt64Atomics");
  need(v12.bufferDeviceAddress, "bufferDeviceAddress");
  if (forced == "Vulkan 1.2") need(false, "Vulkan 1.2");
  return missing;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::vector<Candidate> usable_devices(VkInstance instance) {
  std::uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  const VkResult listed = vkEnumeratePhysicalDevices(instance, &count, devices.data());
  if (listed != VK_INCOMPLETE) check(listed, "vkEnumeratePhysicalDevices");  // a device removed meanwhile: fewer
  devices.resize(count);
  std::vector<Candidate> ok;
  std::string rejected;
  for (auto dev : devices) {
    Candidate c{dev, {}, 0, 0};
    vkGetPhysicalDeviceProperties(dev, &c.props);
    c.family = compute_family(dev, &c.timestamp_bits);
    std::vector<std::string> missing = missing_features(dev, c.props);
    if (c.family == UINT32_MAX) missing.insert(missing.begin(), "a compute queue");
    if (!missing.empty()) {
      rejected += std::string(" ") + c.props.deviceName + " lacks " + joined(missing) + ";";
      continue;
    }
    ok.push_back(c);
  }
  if (ok.empty())
    throw Error("no Vulkan device: " +
                (devices.empty() ? std::string("the loader found no physical device") : "none usable:" + rejected));
  return ok;
}

const Candidate& pick(const std::vector<Candidate>& ok, const std::string& choice) {
  const auto faster = [](const Candidate& a, const Candidate& b) {
    return rank(a.props.deviceType) < rank(b.props.deviceType);
  };
  if (choice.empty()) return *std::min_element(ok.begin(), ok.end(), faster);
  char* end = nullptr;
  const long idx = std::strtol(choice.c_str(), &end, 10);
  if (end && *end == '\0') {
    if (idx < 0 || static_cast<std::size_t>(idx) >= ok.size())
      throw Error("Vulkan device index " + choice + " out of range (" + std::to_string(ok.size()) + " usable)");
    return ok[static_cast<std::size_t>(idx)];
  }
  for (const auto& c : ok)
    if (std::string(c.props.deviceName).find(choice) != std::string::npos) return c;
  throw Error("no Vulkan device matches \"" + choice + "\"");
}

DeviceInfo describe(const Candidate& c) {
  DeviceInfo info;
  info.name = c.props.deviceName;
  info.type = type_name(c.props.deviceType);
  info.max_storage_buffer_range = c.props.limits.maxStorageBufferRange;
  info.max_workgroup_count_x = c.props.limits.maxComputeWorkGroupCount[0];
  info.max_workgroup_count_y = c.props.limits.maxComputeWorkGroupCount[1];
  VkPhysicalDeviceSubgroupProperties sg{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  m3.pNext = &sg;
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &m3;
  vkGetPhysicalDeviceProperties2(c.dev, &p2);
  info.max_allocation = m3.maxMemoryAllocationSize;
  info.max_allocations = c.props.limits.maxMemoryAllocationCount;
  info.subgroup_size = sg.subgroupSize;
  const VkSubgroupFeatureFlags ops = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
                                     VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  info.subgroup_aggregation =
      (sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (sg.supportedOperations & ops) == ops;
  info.timestamps = c.timestamp_bits > 0 && c.props.limits.timestampPeriod > 0;
  info.timestamp_period_ns = c.props.limits.timestampPeriod;
  return info;
}

VkDevice create_device(VkPhysicalDevice physical, std::uint32_t family) {
  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
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
  VkDevice device = VK_NULL_HANDLE;
  check(vkCreateDevice(physical, &dci, nullptr, &device), "vkCreateDevice");
  return device;
}

}  // namespace

Device::Device(const Instance& instance, const std::string& choice) {
  const std::vector<Candidate> ok = usable_devices(instance.handle());
  const Candidate& c = pick(ok, choice);
  physical_ = c.dev;
  queue_family_ = c.family;
  info_ = describe(c);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  for (std::uint32_t h = 0; h < memory_.memoryHeapCount; ++h)
    if (memory_.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info_.device_local_bytes = std::max<std::uint64_t>(info_.device_local_bytes, memory_.memoryHeaps[h].size);
  device_ = create_device(physical_, queue_family_);
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  MemoryPoolOptions po;
  po.max_allocation = info_.max_allocation;
  if (info_.max_allocations > 0) po.max_allocations = info_.max_allocations;  // 0: a driver that did not say
  pool_ = std::make_unique<MemoryPool>(device_, memory_, po);
}

Device::~Device() {
  if (device_) {  // a lost device's wait returns VK_ERROR_DEVICE_LOST at once; the objects are destroyed all the same
    vkDeviceWaitIdle(device_);
    pool_.reset();
    vkDestroyDevice(device_, nullptr);
  }
}

void Device::count_device_bytes(std::int64_t delta) const {
  const std::uint64_t now =
      device_bytes_.fetch_add(static_cast<std::uint64_t>(delta)) + static_cast<std::uint64_t>(delta);
  std::uint64_t peak = peak_device_bytes_.load();
  while (now > peak && !peak_device_bytes_.compare_exchange_weak(peak, now)) {
  }
}

Grid Device::grid(std::uint64_t invocations) const {
  const std::uint64_t groups = std::max<std::uint64_t>((invocations + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE, 1);
  const std::uint64_t x = std::min<std::uint64_t>(groups, info_.max_workgroup_count_x);
  const std::uint64_t y = (groups + x - 1) / x;
  if (y > info_.max_workgroup_count_y)
    throw Error("Vulkan: " + std::to_string(invocations) + " invocations exceed the device's workgroup grid");
  return {static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)};
}

}  // namespace sva::vk
