#pragma once
// The roofline of the vote scatter on a device (`sva bench`): the least work a
// vote can take there. N random weights are quantised and atomically added
// into M bins (bench/roofline/fixed_point_scatter.comp), and the same votes are
// scattered through the 64-bit-key hash table the vote kernel uses, without
// the vote math (hash_scatter.comp). Speed claims for the vote kernel are
// ratios against these, measured on the same device (DESIGN 5). Beside them the vote math alone
// (roofline/vote_math.hpp): whether the math or the table bounds the vote kernel.
#include <cstddef>
#include <string>

#include "roofline/host_reads.hpp"
#include "roofline/vote_math.hpp"

namespace sva::bench {

struct Roofline {
  std::string device;  // name (type)
  std::size_t votes = 0, bins = 0;
  double kernel_ms = 0.0;  // bare fixed-point scatter: best of three
  double votes_per_second = 0.0;
  double hash_kernel_ms = 0.0;         // bare hash scatter: best of three; 0 without timestamps
  double hash_votes_per_second = 0.0;  // 0 without timestamps
  VoteMathRoofline vote_math;          // votes / 16 matches (a CPU device: / 256)
  HostReads host_reads;                // a kernel's result read by the host in place and from a host-cached copy
};

// device: "" = the Vulkan default (env SVA_VK_DEVICE, else prefer a discrete GPU).
Roofline measure_roofline(std::size_t votes, std::size_t bins, const std::string& device);

}  // namespace sva::bench
