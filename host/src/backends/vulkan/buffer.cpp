#include "backends/vulkan/buffer.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "backends/vulkan/device.hpp"
#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/vk_check.hpp"

namespace sva::vk {

// The memory types to try, best first. Mapped buffers (inputs the host writes and
// kernels read, small results): host-visible coherent memory, the device's own
// first (lavapipe, integrated GPUs, a discrete GPU's PCI BAR), else host memory.
// Readback buffers (staging for downloads): host-cached memory first, since the
// host reads a discrete GPU's BAR uncached, at a small fraction of memory speed.
// Device buffers: on integrated GPUs and lavapipe the device's own memory,
// host-visible first (mapped: no staging), then any, host memory last. On a
// discrete GPU device memory the host cannot map (uploads and downloads staged):
// the BAR is a small heap on many boards and slow for the host to read (the
// suspected cause of the H200's seconds-long updates, docs/vulkan-backend.md); and
// no fallback to host memory, since the map or a vote table read across the bus
// would be slower than the CPU reference: a full device is an out-of-memory error
// (the map: a clear error, and the CPU reference under auto; a batch: split further).
std::vector<std::uint32_t> memory_types(const VkPhysicalDeviceMemoryProperties& memory, std::uint32_t allowed,
                                        Memory kind, bool discrete) {
  const VkMemoryPropertyFlags mapped = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  const VkMemoryPropertyFlags local = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  const VkMemoryPropertyFlags cached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
  struct Want {
    VkMemoryPropertyFlags has, lacks;
  };
  std::vector<Want> wants;
  if (kind == Memory::readback)
    wants = {{mapped | cached, 0}, {mapped, 0}};
  else if (kind == Memory::mapped)
    wants = {{mapped | local, 0}, {mapped, 0}};
  else if (!discrete)
    wants = {{mapped | local, 0}, {local, 0}, {mapped, 0}};
  else
    wants = {{local, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT}, {local, 0}};
  std::vector<std::uint32_t> types;
  for (const Want& want : wants)
    for (std::uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
      const VkMemoryPropertyFlags f = memory.memoryTypes[i].propertyFlags;
      if ((allowed & (1u << i)) && (f & want.has) == want.has && (f & want.lacks) == 0 &&
          std::find(types.begin(), types.end(), i) == types.end())
        types.push_back(i);
    }
  if (types.empty()) throw Error("Vulkan: no usable memory type for a storage buffer");
  return types;
}

namespace {

// The injected budget (backends/vulkan/faults.hpp): the device's own memory past it
// fails as the driver's would.
bool over_budget(const Device& device, std::uint64_t bytes) {
  const std::uint64_t budget = faults::memory_budget();
  return budget > 0 && device.device_bytes() + bytes > budget;
}

std::string mib(std::uint64_t bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return b;
}

OutOfMemory out_of_memory(const Device& device, VkResult r, std::size_t bytes) {
  std::string what = "Vulkan: out of memory (" + result_name(r) + ") allocating " + std::to_string(bytes) + " bytes (" +
                     mib(bytes) + ") on " + device.info().name + ", which holds " + mib(device.device_bytes()) +
                     " of sva's buffers";
  if (const std::uint64_t budget = faults::memory_budget())
    what += " (budget SVA_VK_MEMORY_BUDGET_BYTES " + mib(budget) + ")";
  return OutOfMemory(what, bytes);
}

// Past the device's count of live allocations (maxMemoryAllocationCount), even with buffers sharing blocks: an
// out-of-memory error, so that a batch splits further as for a full device, and its words say which limit.
OutOfMemory too_many_allocations(const Device& device, std::size_t bytes) {
  std::string what = "Vulkan: out of memory allocations allocating " + std::to_string(bytes) + " bytes on " +
                     device.info().name + ", which allows " + std::to_string(device.info().max_allocations) +
                     " live at once (maxMemoryAllocationCount)";
  if (const std::uint64_t cap = faults::max_allocations())
    what += " (SVA_VK_MAX_ALLOCATIONS " + std::to_string(cap) + ")";
  return OutOfMemory(what + "; sva holds " + std::to_string(device.pool().live_allocations()) + " holding " +
                         mib(device.pool().held_bytes()),
                     bytes);
}

}  // namespace

Buffer::Buffer(const Device& device, std::size_t bytes, Memory kind, bool never_map, Contents contents)
    : device_(device.handle()), size_(bytes ? bytes : 16) {
  if (size_ > device.info().max_allocation)
    throw OutOfMemory("Vulkan: a buffer of " + std::to_string(size_) +
                          " bytes exceeds the device's largest allocation (" +
                          std::to_string(device.info().max_allocation) + " bytes, maxMemoryAllocationSize)",
                      size_);
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size_;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
              VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device_, &bci, nullptr, &buffer_), "vkCreateBuffer");
  try {
    allocate(device, kind, never_map, contents);
  } catch (...) {
    release();  // the destructor does not run for a failed constructor
    throw;
  }
}

void Buffer::allocate(const Device& device, Memory kind, bool never_map, Contents contents) {
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer_, &req);
  VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  const bool discrete = device.info().type == "discrete";
  for (std::uint32_t type : memory_types(device.memory(), req.memoryTypeBits, kind, discrete)) {
    const VkMemoryPropertyFlags f = device.memory().memoryTypes[type].propertyFlags;
    const bool local = (f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) != 0;
    const bool host_visible = (f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    // A discrete GPU's device buffers are never mapped (memory_types says why).
    const bool map = host_visible && !(kind == Memory::device && (never_map || discrete));
    r = local && over_budget(device, req.size) ? VK_ERROR_OUT_OF_DEVICE_MEMORY
                                               : device.pool().allocate(req, type, map, &range_);
    if (r == VK_SUCCESS) {
      pool_ = &device.pool();
      device.count_buffer();
      device_local_ = local;
      if (device_local_) {
        owner_ = &device;
        counted_ = req.size;
        device.count_device_bytes(static_cast<std::int64_t>(counted_));
      }
      break;
    }
    if (r != VK_ERROR_OUT_OF_DEVICE_MEMORY && r != VK_ERROR_OUT_OF_HOST_MEMORY) break;
  }
  if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY) throw out_of_memory(device, r, size_);
  if (r == VK_ERROR_TOO_MANY_OBJECTS) throw too_many_allocations(device, size_);
  check(r, "vkAllocateMemory");
  check(vkBindBufferMemory(device_, buffer_, range_.memory, range_.offset), "vkBindBufferMemory");
  mapped_ = range_.mapped;
  if (mapped_ && (contents == Contents::zero || faults::poison_uncleared()))
    std::memset(mapped_, contents == Contents::zero ? 0 : 0xa5, size_);
  VkBufferDeviceAddressInfo ai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  ai.buffer = buffer_;
  address_ = vkGetBufferDeviceAddress(device_, &ai);
}

void Buffer::release() {
  if (owner_ && counted_) owner_->count_device_bytes(-static_cast<std::int64_t>(counted_));
  owner_ = nullptr;
  counted_ = 0;
  if (device_ && buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  if (pool_) pool_->free(range_);  // after the buffer bound to it is gone
  pool_ = nullptr;
  range_ = {};
  device_ = VK_NULL_HANDLE;
  buffer_ = VK_NULL_HANDLE;
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
    std::swap(owner_, o.owner_);
    std::swap(counted_, o.counted_);
    std::swap(device_, o.device_);
    std::swap(buffer_, o.buffer_);
    std::swap(pool_, o.pool_);
    std::swap(range_, o.range_);
    std::swap(mapped_, o.mapped_);
    std::swap(size_, o.size_);
    std::swap(address_, o.address_);
    std::swap(device_local_, o.device_local_);
  }
  return *this;
}

}  // namespace sva::vk
