#version 460
// Bare fixed-point scatter: each invocation quantises one float weight and adds
// it into its bin with a 64-bit integer atomic. This is the order-independent
// accumulation rule of the whole engine (DESIGN 4) and, timed on its own, the
// roofline for vote scatter.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer Weights { float weight[]; };
layout(std430, set = 0, binding = 1) readonly buffer Bins { uint bin[]; };
layout(std430, set = 0, binding = 2) buffer Sums { int64_t sums[]; };

layout(push_constant) uniform Push { uint count; uint bin_count; uint base; } pc;  // base: first index of this dispatch

void main() {
  uint i = pc.base + gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint b = bin[i];
  if (b >= pc.bin_count) return;
  atomicAdd(sums[b], SVA_TO_FIXED(weight[i]));
}
