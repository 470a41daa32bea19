#pragma once
// What a vote backend reports about itself through VoteBackend::statistics():
// what runs the votes, where the last update's time went and its counters.
// Every backend fills what it has; the rest stays zero. Reports read it
// through the interface, never by casting to a concrete backend.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include <sva/batch_recognizer.hpp>

namespace sva {

struct BackendStats {
  std::string backend;                    // "cpu" or "vulkan"
  std::string device;                     // what runs the votes: "CPU reference (N threads)" or "GPU name (type)"
  double last_kernel_ms = 0.0;            // GPU time of the last update: vote and fold kernels (0 on the CPU)
  double last_fold_ms = 0.0;              // of which the fold into the beliefs
  double last_host_ms = 0.0;              // host time of the last update (on the CPU, all of it)
  std::size_t map_chunks = 0;             // map chunks in device memory (binding-range limit)
  std::size_t table_slots = 0;            // vote-table slots
  unsigned table_grows = 0;               // vote- or belief-table overflows so far, each grown and rerun
  std::uint32_t validation_messages = 0;  // Vulkan validation warnings and errors (SVA_VK_VALIDATION=1)
  // Device memory held on the backend's device now (the map once, vote tables, beliefs; with a shared engine, of
  // every backend on it), and of it the uploaded map's; 0 on the CPU, and 0 where a device backend does not report
  // it (reports print "n/a" then, not "0 bytes").
  std::uint64_t device_bytes = 0;
  std::uint64_t map_device_bytes = 0;
  // What the device's memory allocations hold (vk::MemoryPool: the buffers' bytes, and the blocks' free ranges),
  // every memory type's; 0 on the CPU.
  std::uint64_t device_held_bytes = 0;
  unsigned band_rebuilds = 0;       // GPU band lists rebuilt from whole belief tables (after a growth or a full list)
  BatchRecognizer::Work last_work;  // what the last vote or vote_and_fold did (the backend's counts; 0 elsewhere)
  double last_belief_growth_ms = 0.0;  // of last_host_ms: growing the beliefs' tables (Vulkan; 0 on the CPU)
  // The last update's submissions (vk::SubmitTimes; 0 on the CPU): recording them, waiting for them, and the device's
  // span from each one's first command to its last (0 without timestamps). With a shared engine, of every backend
  // that submitted meanwhile.
  double last_record_ms = 0.0;
  double last_wait_ms = 0.0;
  double last_device_span_ms = 0.0;
  // The last update's device time by kernel (vk::SubmitTimes::kernels; empty on the CPU and without timestamps),
  // likewise of every backend that submitted meanwhile.
  std::map<std::string, BatchRecognizer::KernelTime> last_kernel_by_pipeline;
  // Device submissions so far (each a round trip: submit, then wait), the estimates' reads of the beliefs included;
  // with a shared engine, of every backend on its device. 0 on the CPU.
  std::uint64_t device_submissions = 0;
  // Device memory allocations so far (a block of the memory pool, or a large buffer's own), likewise of the device;
  // 0 on the CPU.
  std::uint64_t device_allocations = 0;
  // The device: its kind ("discrete", "integrated", "cpu" for lavapipe; "" on the CPU reference) and its largest
  // device-local heap (0 on the CPU).
  std::string device_type;
  std::uint64_t device_memory_bytes = 0;
};

}  // namespace sva
