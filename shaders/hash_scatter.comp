#version 460
// Fixed-point scatter of (key, weight) votes into an open-addressing hash table
// with 64-bit keys: claim a slot with atomicCompSwap on the key, add the
// quantised weight with a 64-bit integer atomicAdd. Linear probing is bounded
// by SVA_HASH_MAX_PROBE; a vote that finds no slot raises the overflow flag and
// the host grows the table and runs again, so no vote is ever dropped.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_hash.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer Keys { uint64_t vote_key[]; };
layout(std430, set = 0, binding = 1) readonly buffer Weights { float vote_weight[]; };
layout(std430, set = 0, binding = 2) buffer TableKeys { uint64_t table_key[]; };
layout(std430, set = 0, binding = 3) buffer TableSums { int64_t table_sum[]; };
layout(std430, set = 0, binding = 4) buffer Status { uint overflow; };

layout(push_constant) uniform Push {
  uint count;      // votes in this chunk
  uint capacity;   // table slots, a power of two
} pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  int64_t units = SVA_TO_FIXED(vote_weight[i]);
  if (units == 0) return;  // the CPU reference drops zero votes too
  uint64_t key = vote_key[i];
  uint mask = pc.capacity - 1u;
  uint slot = uint(sva_hash64(key)) & mask;
  for (uint probe = 0u; probe < SVA_HASH_MAX_PROBE; ++probe) {
    uint64_t prev = atomicCompSwap(table_key[slot], SVA_HASH_EMPTY_KEY, key);
    if (prev == SVA_HASH_EMPTY_KEY || prev == key) {
      atomicAdd(table_sum[slot], units);
      return;
    }
    slot = (slot + 1u) & mask;
  }
  atomicOr(overflow, 1u);
}
