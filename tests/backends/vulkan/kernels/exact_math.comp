#version 460
// Test kernel: sva_div(a[i], b[i]) and sva_sqrt(a[i]) on the device, for the
// agreement contract's test (tests/vulkan/test_exact_math.cpp).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_fast_math.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer A { float a[]; };
layout(std430, binding = 1) readonly buffer B { float b[]; };
layout(std430, binding = 2) writeonly buffer Q { float q[]; };
layout(std430, binding = 3) writeonly buffer R { float r[]; };
layout(push_constant) uniform Push { uint n; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= n) return;
  q[i] = sva_div(a[i], b[i]);
  r[i] = sva_sqrt(a[i]);
}
