#version 460
// Test kernel: the belief's integer arithmetic (sva_belief_math.h) on the
// device, per case, for tests/backends/vulkan/test_belief_math_device.cpp,
// which computes the same with the header compiled as C++. The fold and the
// estimate lean on 64-bit masks, shifts and products; a device that gets one of
// them wrong (the H200 did in another kernel, docs/vulkan-backend.md) shows here.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_belief_math.h"
layout(local_size_x = 64) in;
// Per case: mass, total, eps_units, d, a, b (64-bit), then mass_bits in the low word of a seventh.
layout(std430, binding = 0) readonly buffer In { uint64_t inp[]; };
// Per case: fold units, floor log, exp2_neg units, mul hi, mul lo, msb of a, log2 of (a, b).
layout(std430, binding = 1) writeonly buffer Out { uint64_t outp[]; };
layout(push_constant) uniform Push { uint n; };
void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= n) return;
  uint i = 7u * c, o = 7u * c;
  uint64_t mass = inp[i], total = inp[i + 1u], eps = inp[i + 2u], d = inp[i + 3u], a = inp[i + 4u], b = inp[i + 5u];
  uint mass_bits = uint(inp[i + 6u]);
  outp[o] = sva_fold_units(mass, total, eps);
  outp[o + 1u] = sva_floor_log(total, eps);
  outp[o + 2u] = sva_exp2_neg_units(d, mass_bits);
  SvaU128 p = sva_mul_u64(a, b);
  outp[o + 3u] = p.hi;
  outp[o + 4u] = p.lo;
  outp[o + 5u] = uint64_t(a != 0ul ? sva_msb64(a) : 0u);
  outp[o + 6u] = (a | b) != 0ul ? sva_log2_u128(sva_u128(a, b)) : 0ul;
}
