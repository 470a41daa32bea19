#pragma once
// The device's memory in blocks: buffers take ranges of a few large allocations
// (vkAllocateMemory) rather than one each. A batch held about ten buffers per
// session once estimated (belief table, band list, state, the estimate's reads),
// and every table that grew was a new allocation and a free: each a call into a
// GPU driver's kernel side, and a count many drivers cap at 4096 live allocations
// (maxMemoryAllocationCount), which a batch of about 400 sessions passed
// (issue 52: "tables from a pool"). A buffer larger than a quarter of the
// largest block keeps an allocation of its own (the map, a large batch's vote
// table). Thread-safe: a batch's estimates make their read-back buffers on the
// workers.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

namespace sva::vk {

// Where a buffer's memory lies: a range of a block, or an allocation of its own.
struct MemoryRange {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // the range's first byte, where the caller asked for it mapped
  void* block = nullptr;   // the pool's block; nullptr for an allocation of its own
};

struct MemoryPoolOptions {
  VkDeviceSize first_block = VkDeviceSize{4} << 20;  // a memory type's first block; each next one twice the last
  VkDeviceSize largest_block = VkDeviceSize{64} << 20;
  VkDeviceSize max_allocation = ~VkDeviceSize{0};     // maxMemoryAllocationSize
  std::uint32_t max_allocations = ~std::uint32_t{0};  // maxMemoryAllocationCount (live at once)
};

class MemoryPool {
 public:
  MemoryPool(VkDevice device, const VkPhysicalDeviceMemoryProperties& memory, MemoryPoolOptions options);
  ~MemoryPool();
  MemoryPool(const MemoryPool&) = delete;
  MemoryPool& operator=(const MemoryPool&) = delete;

  // A range for `req` in memory type `type`, mapped when `map` (the type must then be host-visible). Returns the
  // driver's result: VK_SUCCESS, or the error of the last allocation tried (a block failing is retried as an
  // allocation of the request's own size); VK_ERROR_TOO_MANY_OBJECTS when the live allocations are at the device's
  // count.
  VkResult allocate(const VkMemoryRequirements& req, std::uint32_t type, bool map, MemoryRange* out);
  // Gives the range back; a block left empty is freed unless it is its type's last.
  void free(const MemoryRange& range) noexcept;

  std::uint64_t allocations() const;       // vkAllocateMemory calls that succeeded so far
  std::uint32_t live_allocations() const;  // blocks and allocations of their own held now
  std::uint64_t held_bytes() const;        // the bytes those hold

 private:
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0, used = 0;
    std::uint32_t type = 0;
    void* mapped = nullptr;                     // the whole block, where the type is host-visible
    std::map<VkDeviceSize, VkDeviceSize> free;  // offset -> length, coalesced
  };
  VkResult allocate_memory(VkDeviceSize bytes, std::uint32_t type, VkDeviceMemory* memory);
  void free_memory(VkDeviceMemory memory, VkDeviceSize bytes);
  // A range of `req` in `b`, first fit by offset; false when none is free.
  static bool take(Block& b, const VkMemoryRequirements& req, VkDeviceSize* offset);
  static void give_back(Block& b, VkDeviceSize offset, VkDeviceSize size);
  VkResult add_block(const VkMemoryRequirements& req, std::uint32_t type, Block** out);
  VkResult allocate_own(const VkMemoryRequirements& req, std::uint32_t type, bool map, MemoryRange* out);
  bool host_visible(std::uint32_t type) const;

  VkDevice device_;
  VkPhysicalDeviceMemoryProperties memory_;
  MemoryPoolOptions options_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<Block>> blocks_;
  std::uint64_t allocations_ = 0, held_bytes_ = 0;
  std::uint32_t live_ = 0;
};

}  // namespace sva::vk
