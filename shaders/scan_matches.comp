#version 460
// Exclusive prefix sum of the matches of every key item within one map chunk
// (its range clipped to the chunk), so that match_votes.comp can map a flat
// match index to (key item, entry). One workgroup: each invocation sums a
// contiguous block, the block sums are scanned in shared memory, then each
// block is written out. Also writes the indirect dispatch of the match kernel.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_gpu_layout.h"

layout(local_size_x = SVA_SCAN_WIDTH) in;

layout(std430, set = 0, binding = 0) readonly buffer Ranges { SvaGpuRange ranges[]; };
layout(std430, set = 0, binding = 1) writeonly buffer WorkOffsets { uint work_offset[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Result { SvaScanResult result; };

layout(push_constant) uniform Push { SvaScanParams pc; };

shared uint64_t block_sum[SVA_SCAN_WIDTH];

uint clipped(uint k) {
  uint b = max(ranges[k].begin, pc.chunk_begin);
  uint e = min(ranges[k].end, pc.chunk_end);
  return e > b ? e - b : 0u;
}

void main() {
  uint t = gl_LocalInvocationID.x;
  uint per = (pc.key_items + SVA_SCAN_WIDTH - 1u) / SVA_SCAN_WIDTH;
  uint first = min(t * per, pc.key_items);
  uint last = min(first + per, pc.key_items);
  uint64_t s = 0ul;
  for (uint i = 0u; i < SVA_MAX_KEY_ITEMS / SVA_SCAN_WIDTH; ++i) {
    if (first + i >= last) break;
    s += uint64_t(clipped(first + i));
  }
  block_sum[t] = s;
  barrier();
  // Inclusive Hillis-Steele scan of the block sums.
  for (uint d = 1u; d < SVA_SCAN_WIDTH; d <<= 1) {
    uint64_t add = t >= d ? block_sum[t - d] : 0ul;
    barrier();
    block_sum[t] += add;
    barrier();
  }
  uint64_t running = block_sum[t] - s;  // exclusive prefix of this block
  uint64_t total = block_sum[SVA_SCAN_WIDTH - 1u];
  bool fits = total <= uint64_t(0xffffffffu);
  for (uint i = 0u; i < SVA_MAX_KEY_ITEMS / SVA_SCAN_WIDTH; ++i) {
    if (first + i >= last) break;
    work_offset[first + i] = fits ? uint(running) : 0u;
    running += uint64_t(clipped(first + i));
  }
  if (t == 0u) {
    work_offset[pc.key_items] = fits ? uint(total) : 0u;
    uint groups = fits ? uint((total + uint64_t(SVA_WORKGROUP_SIZE - 1)) / uint64_t(SVA_WORKGROUP_SIZE)) : 0u;
    uint gx = min(groups, pc.max_groups_x);
    result.groups_x = gx;
    result.groups_y = gx == 0u ? 0u : (groups + gx - 1u) / gx;
    result.groups_z = 1u;
    result.total = fits ? uint(total) : 0u;
    result.too_many = fits ? 0u : 1u;
  }
}
