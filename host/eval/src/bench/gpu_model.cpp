#include "bench/gpu_model.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace sva::bench {

const DeviceFigures& h100_sxm() {
  static const DeviceFigures d{"NVIDIA H100 SXM5 80 GB",
                               "HBM3 3.35 TB/s (NVIDIA H100 datasheet); assumed: atomics 2e10-1e11/s, "
                               "50-100 us per submission",
                               3.35e12,
                               2e10,
                               1e11,
                               50e-6,
                               100e-6};
  return d;
}

nlohmann::json model_update(const nlohmann::json& work, const DeviceFigures& device, std::size_t sessions) {
  if (work.is_null()) return nullptr;
  const nlohmann::json& device_count = work["vote_table_atomics"];  // null on the CPU
  const double counted = device_count.is_number() ? device_count.get<double>() : 0.0;
  const double vote_atomics = counted > 0 ? counted : 2.0 * work["votes"].get<double>();
  const double atomics = vote_atomics + 3.0 * work["bins"].get<double>();
  const nlohmann::json& b = work["bytes"];
  const double bytes = b["map"].get<double>() + b["vote_tables"].get<double>() + b["fold"].get<double>();
  const double memory_s = bytes / device.memory_bytes_per_second;
  // Best case: atomics at the high rate overlap the memory traffic; worst: the low rate, one after the other.
  const double share = 1.0 / static_cast<double>(std::max<std::size_t>(sessions, 1));
  const double low_s = device.fixed_seconds_low * share + std::max(memory_s, atomics / device.atomics_per_second_high);
  const double high_s = device.fixed_seconds_high * share + memory_s + atomics / device.atomics_per_second_low;
  return {{"device", device.name},          {"figures", device.source}, {"atomics", atomics},
          {"atomics_counted", counted > 0}, {"bytes", bytes},           {"low_ms", 1e3 * low_s},
          {"high_ms", 1e3 * high_s}};
}

}  // namespace sva::bench
