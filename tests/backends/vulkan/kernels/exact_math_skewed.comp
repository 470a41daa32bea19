#version 460
// Test kernel: exact_math.comp with the fast paths' first estimates pushed off
// by SVA_EXACT_ESTIMATE_SKEW units, so that lavapipe (whose own division and
// square root are exact) runs the corrections (a few units) and the fallbacks
// (far off) that a less exact device needs (tests/backends/vulkan/test_exact_math.cpp).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#define SVA_EXACT_ESTIMATE_SKEW skew
layout(push_constant) uniform Push { uint n; int skew; };
#include "sva_shared.h"
#include "sva_fast_math.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer A { float a[]; };
layout(std430, binding = 1) readonly buffer B { float b[]; };
layout(std430, binding = 2) writeonly buffer Q { float q[]; };
layout(std430, binding = 3) writeonly buffer R { float r[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= n) return;
  q[i] = sva_div(a[i], b[i]);
  r[i] = sva_sqrt(a[i]);
}
