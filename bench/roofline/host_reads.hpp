#pragma once
// What a host read of a kernel's result costs on a device (`sva bench`'s line "host reads"): words the device wrote
// into a mapped buffer, summed by the host in place, against the same words copied by the device into a readback
// buffer (host-cached memory) in the submission that wrote them and summed there. On a discrete GPU a mapped
// buffer is the device's memory behind its PCI BAR, which the host reads uncached, one bus round trip per load:
// what gpu::add_mirror_read avoids for an update's counters, key ranges and statuses (issue 52).
#include <cstddef>

#include "backends/vulkan/context.hpp"

namespace sva::bench {

struct HostReads {
  std::size_t loads = 0;              // 8-byte loads per pass
  double mapped_ns_per_load = 0.0;    // in place: best of three passes
  double readback_ns_per_load = 0.0;  // from the host-cached copy: best of three passes
  bool mapped_device_local = false;   // the mapped buffer is the device's own memory (a discrete GPU's BAR)
  bool sums_agree = false;            // both passes read the words the device wrote
};

HostReads measure_host_reads(vk::Context& ctx, std::size_t loads = 1 << 15);

}  // namespace sva::bench
