#pragma once
// A model of a GPU's kernel time per update from the work an update did (docs/vulkan-backend.md, "Work and an
// estimate for an H100"): the atomics on the hash tables at an assumed rate, the bytes at the device's published
// memory bandwidth. An estimate to check against the first measurement on the device, not a measurement.
#include <nlohmann/json_fwd.hpp>
#include <string>

namespace sva::bench {

struct DeviceFigures {
  std::string name;
  std::string source;              // where the figures come from
  double memory_bytes_per_second;  // published
  // Random 64-bit atomics on tables that fit the L2 cache: not published; a range (the bench's hash-scatter
  // roofline measures the device's own).
  double atomics_per_second_low, atomics_per_second_high;
  // A submission's fixed cost: its fence and about ten dependent dispatches (keys, scan, votes, the fold's passes),
  // a range, assumed; a batch shares it among its sessions.
  double fixed_seconds_low, fixed_seconds_high;
};

// NVIDIA H100 SXM5 80 GB: HBM3 at 3.35 TB/s (NVIDIA's H100 datasheet); the atomic range is assumed.
const DeviceFigures& h100_sxm();

// The model for one session-update, from a checkpoint's "work_per_update" (null where the run counted no work) in
// a submission of `sessions`: {"atomics", "bytes", "low_ms", "high_ms", "atomics_counted"}. The vote tables' atomics
// are the device's count where the run has one (Vulkan), else two per vote (a compare-and-swap and an add, no
// pre-aggregation); the fold adds three per bin (the pair's total, the key's reservation, the offset's add: a lower
// bound).
nlohmann::json model_update(const nlohmann::json& work, const DeviceFigures& device, std::size_t sessions);

}  // namespace sva::bench
