#pragma once
// Fault injection for tests: the GPU faults a shared or failing device gives,
// made on demand on any device (lavapipe included), so that the paths that
// handle them run in ctest. Each is set by an environment variable (read once,
// at first use, so that CLI tests reach it) or by a test hook that overrides it:
//   SVA_VK_MEMORY_BUDGET_BYTES=N   the device's own memory past N bytes (all live
//                                  buffers of one device) fails to allocate with
//                                  VK_ERROR_OUT_OF_DEVICE_MEMORY, as a full GPU would;
//   SVA_VK_MAX_ALLOCATIONS=N       the device holds at most N memory allocations at
//                                  once (maxMemoryAllocationCount, 4096 on many drivers):
//                                  one more fails with VK_ERROR_TOO_MANY_OBJECTS;
//   SVA_VK_FAULT_DEVICE_LOST_AFTER=N  the submission after the next N returns
//                                  VK_ERROR_DEVICE_LOST (once; later devices work);
//   SVA_VK_FAULT_MISSING_FEATURE=F the device reports feature F (shaderInt64,
//                                  shaderBufferInt64Atomics, bufferDeviceAddress,
//                                  Vulkan 1.2) as missing;
//   SVA_VK_POISON_UNCLEARED=1      a mapped buffer made with undefined contents
//                                  (vk::Contents::undefined) starts as 0xa5 bytes, not
//                                  as the zero pages a fresh allocation mostly gets, so
//                                  that a caller that forgets to fill it reads garbage.
#include <cstdint>
#include <optional>
#include <string>

namespace sva::vk::faults {

// 0 = no budget.
std::uint64_t memory_budget();
void set_memory_budget(std::uint64_t bytes);  // tests; 0 clears

// 0 = the device's own count only.
std::uint64_t max_allocations();
void set_max_allocations(std::uint64_t count);  // tests; 0 clears

// Whether this submission is to fail as lost (counts submissions down; fires once).
bool take_device_loss();
void lose_device_after(std::uint64_t submissions);  // tests
void clear_device_loss();                           // tests

// The feature a device is to lack ("" = none).
std::string missing_feature();
void set_missing_feature(const std::string& feature);  // tests; "" clears

// Whether buffers of undefined contents are poisoned.
bool poison_uncleared();
void set_poison_uncleared(bool on);  // tests

}  // namespace sva::vk::faults
