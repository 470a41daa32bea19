// The device's memory in blocks (backends/vulkan/memory_pool.hpp, issue 52's "tables from a pool"): buffers share
// a few allocations, each keeps its own bytes, freed ranges are reused, and a device's cap on live allocations
// (maxMemoryAllocationCount) is met with a clear error, not the driver's.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <tuple>
#include <vector>

#include <sva/base/rng.hpp>

#include "backends/vulkan/buffer.hpp"
#include "backends/vulkan/context.hpp"
#include "backends/vulkan/faults.hpp"
#include "backends/vulkan/memory_pool.hpp"
#include "backends/vulkan/vk_check.hpp"
#include "vk_test_support.hpp"

using namespace sva;

namespace {

// The first memory type a storage buffer may use (the tests' pools allocate raw ranges of it).
std::uint32_t storage_type(const vk::Context& ctx) {
  vk::Buffer probe(ctx.device(), 64, vk::Memory::mapped);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device().handle(), probe.handle(), &req);
  return vk::memory_types(ctx.device().memory(), req.memoryTypeBits, vk::Memory::mapped, false).front();
}

VkMemoryRequirements request(VkDeviceSize size, VkDeviceSize alignment = 256) { return {size, alignment, ~0u}; }

struct MaxAllocationsCleared {
  ~MaxAllocationsCleared() { vk::faults::set_max_allocations(0); }
};

}  // namespace

TEST_CASE("memory pool: a thousand small buffers share a few allocations, each its own bytes, staged ones too") {
  auto ctx = test::vulkan_context_or_skip();
  const std::uint64_t a0 = ctx->allocations(), b0 = ctx->buffers_made();
  std::vector<vk::Buffer> buffers;
  for (int i = 0; i < 1000; ++i) buffers.emplace_back(ctx->device(), 4096 + 64 * (i % 7), vk::Memory::mapped);
  CHECK(ctx->buffers_made() - b0 == 1000);
  CHECK(ctx->allocations() - a0 <= 4);  // blocks of 4, 8 and 16 MiB hold about 5 MiB
  // Each buffer its own range: a pattern written through every mapping reads back whole.
  for (std::size_t i = 0; i < buffers.size(); ++i) std::memset(buffers[i].data(), static_cast<int>(i % 251), 4096);
  std::vector<VkDeviceAddress> starts;
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const auto* p = buffers[i].as<std::uint8_t>();
    REQUIRE(std::all_of(p, p + 4096, [&](std::uint8_t v) { return v == i % 251; }));
    starts.push_back(buffers[i].device_address());
  }
  std::sort(starts.begin(), starts.end());
  CHECK(std::adjacent_find(starts.begin(), starts.end()) == starts.end());
  // Buffers the host does not map (a discrete GPU's device memory) in ranges of shared blocks: uploads and downloads
  // go through staging copies at each buffer's offset.
  std::vector<vk::Buffer> staged;
  for (int i = 0; i < 50; ++i) staged.emplace_back(ctx->device(), 1000 + 8 * i, vk::Memory::device, true);
  for (std::size_t i = 0; i < staged.size(); ++i) {
    std::vector<std::uint32_t> words(staged[i].size() / 4);
    std::iota(words.begin(), words.end(), static_cast<std::uint32_t>(1000 * i));
    ctx->upload(staged[i], words.data(), words.size() * 4);
  }
  for (std::size_t i = 0; i < staged.size(); ++i) {
    std::vector<std::uint32_t> back(staged[i].size() / 4);
    ctx->download(staged[i], back.data(), back.size() * 4);
    INFO("staged buffer " << i);
    CHECK(back.front() == 1000 * i);
    CHECK(back.back() == 1000 * i + back.size() - 1);
  }
}

TEST_CASE("memory pool: freed ranges join and are taken again, and an empty block goes unless it is its type's last") {
  auto ctx = test::vulkan_context_or_skip();
  vk::MemoryPoolOptions o;
  o.first_block = 1 << 16;
  o.largest_block = 1 << 18;
  vk::MemoryPool pool(ctx->device().handle(), ctx->device().memory(), o);
  const std::uint32_t type = storage_type(*ctx);
  vk::MemoryRange a, b, c;
  REQUIRE(pool.allocate(request(1 << 12), type, true, &a) == VK_SUCCESS);
  REQUIRE(pool.allocate(request(1 << 12), type, true, &b) == VK_SUCCESS);
  REQUIRE(pool.allocate(request(1 << 12), type, true, &c) == VK_SUCCESS);
  CHECK(pool.allocations() == 1);
  CHECK(a.memory == b.memory);
  CHECK(b.offset == a.offset + (1 << 12));
  CHECK(static_cast<char*>(b.mapped) - static_cast<char*>(a.mapped) == 1 << 12);
  // a and b freed: one range of twice the size where they were.
  pool.free(b);
  pool.free(a);
  vk::MemoryRange ab;
  REQUIRE(pool.allocate(request(1 << 13), type, false, &ab) == VK_SUCCESS);
  CHECK(ab.offset == a.offset);
  CHECK(ab.mapped == nullptr);  // not asked for
  CHECK(pool.allocations() == 1);
  // Alignment kept past an odd-sized range.
  vk::MemoryRange odd, aligned;
  REQUIRE(pool.allocate(request(100, 4), type, false, &odd) == VK_SUCCESS);
  REQUIRE(pool.allocate(request(64, 1024), type, false, &aligned) == VK_SUCCESS);
  CHECK(aligned.offset % 1024 == 0);
  // Past the first block: a second; larger than a quarter of the largest block: its own.
  vk::MemoryRange big, own;
  REQUIRE(pool.allocate(request(56 << 10), type, false, &big) == VK_SUCCESS);  // more than the first has left
  CHECK(big.memory != a.memory);
  CHECK(pool.held_bytes() == (1 << 16) + (1 << 18));  // at least four times the request
  REQUIRE(pool.allocate(request((1 << 16) + 8), type, true, &own) == VK_SUCCESS);
  CHECK(own.block == nullptr);
  CHECK(own.mapped != nullptr);
  CHECK(pool.live_allocations() == 3);
  pool.free(own);
  pool.free(big);  // its block empty, not its type's last: freed
  CHECK(pool.live_allocations() == 1);
  CHECK(pool.held_bytes() == 1 << 16);
  for (const vk::MemoryRange* r : {&ab, &c, &odd, &aligned}) pool.free(*r);
  CHECK(pool.live_allocations() == 1);  // the last block kept for the next request
  vk::MemoryRange again;
  REQUIRE(pool.allocate(request(1 << 16), type, false, &again) == VK_SUCCESS);  // the whole block, once coalesced
  CHECK(pool.allocations() == 3);
  pool.free(again);
}

TEST_CASE("memory pool: a device's cap on live allocations is an out-of-memory error naming it, nothing lost") {
  auto ctx = test::vulkan_context_or_skip();
  MaxAllocationsCleared cleared;
  std::vector<vk::Buffer> kept;
  kept.emplace_back(ctx->device(), 64, vk::Memory::mapped);  // a block of the pool, if none was live
  const std::uint32_t live = ctx->device().pool().live_allocations();
  vk::faults::set_max_allocations(live + 1);
  // Small buffers still fit: they share the blocks held.
  for (int i = 0; i < 100; ++i) kept.emplace_back(ctx->device(), 1024, vk::Memory::mapped);
  CHECK(ctx->device().pool().live_allocations() == live);
  vk::Buffer large(ctx->device(), 40 << 20, vk::Memory::mapped);  // its own allocation: the last the cap allows
  try {
    vk::Buffer more(ctx->device(), 40 << 20, vk::Memory::mapped);
    FAIL("expected an out-of-memory error");
  } catch (const vk::OutOfMemory& e) {
    const std::string m = e.what();
    CHECK_THAT(m, Catch::Contains("maxMemoryAllocationCount") && Catch::Contains("SVA_VK_MAX_ALLOCATIONS"));
    CHECK(e.bytes() == std::size_t{40} << 20);
  }
  CHECK(ctx->device().pool().live_allocations() == live + 1);
  vk::faults::set_max_allocations(0);
  vk::Buffer after(ctx->device(), 40 << 20, vk::Memory::mapped);
  std::memset(after.data(), 1, after.size());
  CHECK(kept.back().as<std::uint8_t>()[0] == 0);  // the others' bytes untouched
}

TEST_CASE("memory pool: random takes and frees keep every range apart and in its block, and join back whole") {
  // 3,000 random operations on small blocks (the series, and allocations of their own, both reached): no two live
  // ranges of one allocation overlap, each lies within its block and keeps its alignment, and once every range is
  // freed the last block is one free range again.
  auto ctx = test::vulkan_context_or_skip();
  vk::MemoryPoolOptions o;
  o.first_block = 1 << 16;
  o.largest_block = 1 << 20;
  vk::MemoryPool pool(ctx->device().handle(), ctx->device().memory(), o);
  const std::uint32_t type = storage_type(*ctx);
  util::Rng rng(52, 7);
  std::vector<vk::MemoryRange> live;
  std::vector<VkDeviceSize> alignment;
  std::size_t own = 0;
  for (int op = 0; op < 3000; ++op) {
    if (!live.empty() && rng.below(5) < 2) {  // two in five operations free a range
      const std::size_t i = rng.below(live.size());
      pool.free(live[i]);
      live.erase(live.begin() + static_cast<std::ptrdiff_t>(i));
      alignment.erase(alignment.begin() + static_cast<std::ptrdiff_t>(i));
      continue;
    }
    const VkDeviceSize a = VkDeviceSize{1} << rng.below(13);                               // 1 to 4096
    const VkDeviceSize size = 1 + rng.below(rng.below(16) == 0 ? 400u << 10 : 20u << 10);  // some past a quarter
    vk::MemoryRange r;
    REQUIRE(pool.allocate(request(size, a), type, false, &r) == VK_SUCCESS);
    own += r.block == nullptr;
    live.push_back(r);
    alignment.push_back(a);
  }
  CHECK(own > 0);
  CHECK(pool.live_allocations() > 2);
  std::vector<std::size_t> order(live.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return std::tie(live[x].memory, live[x].offset) < std::tie(live[y].memory, live[y].offset);
  });
  for (std::size_t k = 0; k < order.size(); ++k) {
    const vk::MemoryRange& r = live[order[k]];
    CHECK(r.offset % alignment[order[k]] == 0);
    if (k > 0 && live[order[k - 1]].memory == r.memory)
      REQUIRE(live[order[k - 1]].offset + live[order[k - 1]].size <= r.offset);
  }
  for (const vk::MemoryRange& r : live) pool.free(r);
  CHECK(pool.live_allocations() == 1);
  // The kept block, whole again: filled to its last byte by pieces of at most a quarter of the largest block (larger
  // ones take allocations of their own), without a new allocation.
  const std::uint64_t held = pool.held_bytes(), made = pool.allocations();
  const VkDeviceSize piece = std::min<VkDeviceSize>(held, o.largest_block / 4);
  REQUIRE(held % piece == 0);
  std::vector<vk::MemoryRange> pieces(held / piece);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    REQUIRE(pool.allocate(request(piece, 1), type, false, &pieces[k]) == VK_SUCCESS);
    CHECK(pieces[k].offset == k * piece);
  }
  CHECK(pool.allocations() == made);
  for (const vk::MemoryRange& r : pieces) pool.free(r);
}
