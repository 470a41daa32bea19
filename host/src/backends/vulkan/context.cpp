#include "backends/vulkan/context.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace sva::vk {

ContextOptions Context::from_environment() {
  ContextOptions o;
  if (const char* d = std::getenv("SVA_VK_DEVICE")) o.device = d;
  if (const char* v = std::getenv("SVA_VK_VALIDATION")) o.validation = std::string(v) == "1";
  if (const char* v = std::getenv("SVA_VK_STAGING")) o.force_staging = std::string(v) == "1";
  if (const char* v = std::getenv("SVA_VK_SERIAL")) o.serial_dispatches = std::string(v) == "1";
  if (const char* v = std::getenv("SVA_VK_TIMESTAMPS")) o.timestamps = std::string(v) != "0";
  return o;
}

Context::Context(const ContextOptions& options)
    : instance_(options.validation),
      device_(instance_, options.device),
      commands_(device_, options.serial_dispatches, options.timestamps),
      force_staging_(options.force_staging) {}

Buffer Context::create_device_buffer(std::size_t bytes) {
  Buffer b(device_, bytes, Memory::device, force_staging_);
  if (!b.mapped()) run({}, nullptr, {{&b, 0u, 0, 0}});  // mapped memory is zeroed by the host
  return b;
}

// Staging moves at most this much at a time, so an upload of a large map
// needs no second copy of it in host memory.
constexpr std::size_t kStagingBytes = std::size_t{64} << 20;

void Context::upload(Buffer& dst, const void* src, std::size_t bytes, std::size_t offset) {
  if (offset + bytes > dst.size()) throw std::logic_error("Context::upload: range not in the buffer");
  if (bytes == 0) return;
  if (dst.mapped()) {
    std::memcpy(static_cast<std::uint8_t*>(dst.data()) + offset, src, bytes);
    return;
  }
  std::lock_guard lock(mutex_);
  Buffer temporary;
  Buffer& staging = staging_for(upload_staging_, temporary, Memory::mapped, bytes);
  for (std::size_t done = 0; done < bytes; done += staging.size()) {
    const std::size_t n = std::min(staging.size(), bytes - done);
    std::memcpy(staging.data(), static_cast<const std::uint8_t*>(src) + done, n);
    commands_.copy({{&staging, &dst, 0, offset + done, n}});
  }
}

Buffer& Context::staging_for(Buffer& kept, Buffer& temporary, Memory kind, std::size_t bytes) {
  // Small transfers (an estimate's state words, histograms, candidates, a batch's counters) share a kept buffer,
  // grown to the largest of them (a power of two, at most 1 MiB): an allocation per transfer cost more than the
  // transfer on a discrete GPU. Large ones (the map's upload, a whole table) take a buffer of their own for the
  // call, so that no 64 MiB of the device's small host-visible window stays held.
  constexpr std::size_t kKept = std::size_t{1} << 20;
  const std::size_t want = std::min(bytes, kStagingBytes);
  if (want > kKept) {
    temporary = Buffer(device_, want, kind);
    return temporary;
  }
  if (kept.size() < want) kept = Buffer(device_, std::bit_ceil(std::max(want, std::size_t{4096})), kind);
  return kept;
}

void Context::download(const Buffer& src, void* dst, std::size_t bytes, std::size_t offset) {
  if (offset + bytes > src.size()) throw std::logic_error("Context::download: range not in the buffer");
  if (bytes == 0) return;
  if (src.mapped()) {
    std::memcpy(dst, static_cast<const std::uint8_t*>(src.data()) + offset, bytes);
    return;
  }
  std::lock_guard lock(mutex_);
  Buffer temporary;
  Buffer& staging = staging_for(readback_staging_, temporary, Memory::readback, bytes);
  for (std::size_t done = 0; done < bytes; done += staging.size()) {
    const std::size_t n = std::min(staging.size(), bytes - done);
    commands_.copy({{&src, &staging, offset + done, 0, n}});
    std::memcpy(static_cast<std::uint8_t*>(dst) + done, staging.data(), n);
  }
}

}  // namespace sva::vk
