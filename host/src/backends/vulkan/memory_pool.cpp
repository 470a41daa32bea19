#include "backends/vulkan/memory_pool.hpp"

#include <algorithm>
#include <bit>
#include <iterator>
#include <stdexcept>

#include "backends/vulkan/faults.hpp"

namespace sva::vk {

namespace {

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize alignment) {
  return alignment > 1 ? (v + alignment - 1) / alignment * alignment : v;
}

}  // namespace

MemoryPool::MemoryPool(VkDevice device, const VkPhysicalDeviceMemoryProperties& memory, MemoryPoolOptions options)
    : device_(device), memory_(memory), options_(options) {
  options_.largest_block = std::min(options_.largest_block, options_.max_allocation);
  options_.first_block = std::min(options_.first_block, options_.largest_block);
}

MemoryPool::~MemoryPool() {
  for (const auto& b : blocks_) vkFreeMemory(device_, b->memory, nullptr);  // unmaps a mapped block
}

bool MemoryPool::host_visible(std::uint32_t type) const {
  return (memory_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
}

VkResult MemoryPool::allocate_memory(VkDeviceSize bytes, std::uint32_t type, VkDeviceMemory* memory) {
  const std::uint64_t injected = faults::max_allocations();
  const std::uint64_t cap =
      injected ? std::min<std::uint64_t>(injected, options_.max_allocations) : options_.max_allocations;
  if (live_ >= cap) return VK_ERROR_TOO_MANY_OBJECTS;
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.pNext = &flags;
  mai.allocationSize = bytes;
  mai.memoryTypeIndex = type;
  const VkResult r = vkAllocateMemory(device_, &mai, nullptr, memory);
  if (r == VK_SUCCESS) {
    ++allocations_;
    ++live_;
    held_bytes_ += bytes;
  }
  return r;
}

void MemoryPool::free_memory(VkDeviceMemory memory, VkDeviceSize bytes) {
  vkFreeMemory(device_, memory, nullptr);
  --live_;
  held_bytes_ -= bytes;
}

bool MemoryPool::take(Block& b, const VkMemoryRequirements& req, VkDeviceSize* offset) {
  for (auto it = b.free.begin(); it != b.free.end(); ++it) {
    const VkDeviceSize start = it->first, end = it->first + it->second;
    const VkDeviceSize at = align_up(start, req.alignment);
    if (at + req.size > end) continue;
    b.free.erase(it);
    if (at > start) b.free.emplace(start, at - start);
    if (at + req.size < end) b.free.emplace(at + req.size, end - at - req.size);
    b.used += req.size;
    *offset = at;
    return true;
  }
  return false;
}

void MemoryPool::give_back(Block& b, VkDeviceSize offset, VkDeviceSize size) {
  b.used -= size;
  auto next = b.free.lower_bound(offset);
  if (next != b.free.end() && offset + size == next->first) {  // joins the free range after it
    size += next->second;
    next = b.free.erase(next);
  }
  if (next != b.free.begin()) {
    auto prev = std::prev(next);
    if (prev->first + prev->second == offset) {  // and the one before
      prev->second += size;
      return;
    }
  }
  b.free.emplace(offset, size);
}

// A new block of `type`: twice its type's largest so far (the first `first_block`), and at least four times the
// request; at most `largest_block` and an eighth of the type's heap (a discrete GPU's BAR is a heap of 256 MiB on many
// boards, where the inputs' mapped buffers live). Where the driver refuses it, smaller ones down to the request's size.
VkResult MemoryPool::add_block(const VkMemoryRequirements& req, std::uint32_t type, Block** out) {
  const VkDeviceSize heap = memory_.memoryHeaps[memory_.memoryTypes[type].heapIndex].size;
  const VkDeviceSize largest = std::max(std::min(options_.largest_block, std::bit_floor(heap / 8)), req.size);
  VkDeviceSize size = options_.first_block;
  for (const auto& b : blocks_)
    if (b->type == type) size = std::max(size, std::min(2 * b->size, largest));
  size = std::min(std::max(size, std::bit_ceil(4 * req.size)), largest);
  auto b = std::make_unique<Block>();
  b->type = type;
  VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  for (; size >= req.size; size /= 2) {
    r = allocate_memory(size, type, &b->memory);
    if (r != VK_ERROR_OUT_OF_DEVICE_MEMORY && r != VK_ERROR_OUT_OF_HOST_MEMORY) break;
  }
  if (r != VK_SUCCESS) return r;
  b->size = size;
  b->free.emplace(0, size);
  if (host_visible(type)) {
    const VkResult m = vkMapMemory(device_, b->memory, 0, VK_WHOLE_SIZE, 0, &b->mapped);
    if (m != VK_SUCCESS) {
      free_memory(b->memory, size);
      return m;
    }
  }
  blocks_.push_back(std::move(b));
  *out = blocks_.back().get();
  return VK_SUCCESS;
}

VkResult MemoryPool::allocate_own(const VkMemoryRequirements& req, std::uint32_t type, bool map, MemoryRange* out) {
  MemoryRange r;
  const VkResult a = allocate_memory(req.size, type, &r.memory);
  if (a != VK_SUCCESS) return a;
  r.size = req.size;
  if (map) {
    const VkResult m = vkMapMemory(device_, r.memory, 0, VK_WHOLE_SIZE, 0, &r.mapped);
    if (m != VK_SUCCESS) {
      free_memory(r.memory, r.size);
      return m;
    }
  }
  *out = r;
  return VK_SUCCESS;
}

VkResult MemoryPool::allocate(const VkMemoryRequirements& req, std::uint32_t type, bool map, MemoryRange* out) {
  if (map && !host_visible(type)) throw std::logic_error("MemoryPool: a mapped range of memory the host cannot see");
  std::lock_guard<std::mutex> lock(mutex_);
  if (req.size > options_.largest_block / 4) return allocate_own(req, type, map, out);
  Block* block = nullptr;
  VkDeviceSize offset = 0;
  for (const auto& b : blocks_)
    if (b->type == type && take(*b, req, &offset)) {
      block = b.get();
      break;
    }
  if (!block) {
    const VkResult r = add_block(req, type, &block);
    if (r != VK_SUCCESS) return r;
    if (!take(*block, req, &offset)) throw std::logic_error("MemoryPool: a new block without room for its request");
  }
  out->memory = block->memory;
  out->offset = offset;
  out->size = req.size;
  out->mapped = map ? static_cast<char*>(block->mapped) + offset : nullptr;
  out->block = block;
  return VK_SUCCESS;
}

void MemoryPool::free(const MemoryRange& range) noexcept {
  if (!range.memory) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!range.block) {
    free_memory(range.memory, range.size);  // unmaps it
    return;
  }
  auto it = std::find_if(blocks_.begin(), blocks_.end(), [&](const auto& b) { return b.get() == range.block; });
  if (it == blocks_.end()) return;  // not this pool's: a buffer's release must not throw, and frees nothing
  Block& b = **it;
  give_back(b, range.offset, range.size);
  if (b.used > 0) return;
  const bool last =
      std::none_of(blocks_.begin(), blocks_.end(), [&](const auto& o) { return o.get() != &b && o->type == b.type; });
  if (last) return;  // kept: a batch whose tables all moved would otherwise free and allocate it again at once
  free_memory(b.memory, b.size);
  blocks_.erase(it);
}

std::uint64_t MemoryPool::allocations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return allocations_;
}

std::uint32_t MemoryPool::live_allocations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return live_;
}

std::uint64_t MemoryPool::held_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return held_bytes_;
}

}  // namespace sva::vk
