#version 460
// Bare hash scatter of (key, weight) votes, the vote kernel's scatter without
// the vote math: the roofline of hashed voting on a device (sva bench).
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

#include "sva_hash_scatter.glsl"

layout(push_constant) uniform Push {
  uint count;      // votes in this chunk
  uint capacity;   // table slots, a power of two
} pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  int64_t units = SVA_TO_FIXED(vote_weight[i]);
  if (units == 0) return;  // the CPU reference drops zero votes too
  sva_hash_scatter(vote_key[i], units, pc.capacity);
}
