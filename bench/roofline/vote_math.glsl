// The vote math of `sva bench`'s roofline, without the map, the owner rule or the table (included by
// vote_math.comp, the engine's exact division and square root, and vote_math_device_division.comp, the device's own):
// one invocation per match aligns it, plans its beta samples and works out every sample's pose bin and fixed-point
// mass (shaders/include/sva_vote_math.h, the engine's text), and writes a checksum of them so that nothing is left
// out. Set beside the bare hash scatter, it says what bounds the vote kernel on a device.
#include "sva_shared.h"
#include "sva_vote_math.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

// Per match: four patches (p, n, conf: 7 floats each: a1 b1 a2 b2).
layout(std430, binding = 0) readonly buffer In { float inp[]; };
// Per match: the checksum of its samples' keys, of their masses, and the samples inside the pose space.
layout(std430, binding = 1) writeonly buffer Out { uint outp[]; };
layout(push_constant) uniform Push {
  uint n;
  int kind;
  int translation_bins;
  float translation_min;
  float translation_width;
  int rotation_bins;
  float rotation_width;
};

SvaPatch patch_at(uint base) {
  SvaPatch p;
  p.p = vec3(inp[base], inp[base + 1u], inp[base + 2u]);
  p.n = vec3(inp[base + 3u], inp[base + 4u], inp[base + 5u]);
  p.conf = inp[base + 6u];
  return p;
}

void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= n) return;
  uint b = c * 28u;
  SvaAlignment al = sva_align(patch_at(b), patch_at(b + 7u), patch_at(b + 14u), patch_at(b + 21u));
  SvaPoseGrid grid =
      sva_pose_grid(kind, translation_bins, translation_min, translation_width, rotation_bins, rotation_width);
  SvaBetaPlan plan = sva_beta_plan(al, grid);
  float scale = sva_vote_scale(1.0f, sva_beta_weight_sum(plan));
  uint keys = 0u, masses = 0u, inside = 0u;
  for (int i = 0; i < SVA_MAX_BETA_SAMPLES; ++i) {
    if (i >= plan.n) break;
    precise float weight = sva_beta_weight(plan, i) * scale;
    SvaVote v = sva_vote(al, plan, grid, 1u, weight, i);
    keys = keys * 31u + (uint(v.key & 0xffffffffUL) ^ uint(v.key >> 32));
    masses += uint(v.mass & 0xffffffffL);
    inside += uint(v.inside);
  }
  outp[3u * c] = keys;
  outp[3u * c + 1u] = masses;
  outp[3u * c + 2u] = inside;
}
