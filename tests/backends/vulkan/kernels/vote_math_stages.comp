#version 460
// Test kernel: the shared vote math of one match, stage by stage, on the device
// (tests/backends/vulkan/test_vote_math_stages.cpp compares every stage with the
// same header compiled as C++): the alignment, the beta plan, the weight sum
// and the scale, then every sample's weight, pose bin and fixed-point mass.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_vote_math.h"
#include "sva_match_likelihood.h"
layout(local_size_x = 64) in;
// Per case: four patches (p, n, conf: 7 floats each: a1 b1 a2 b2), then the likelihood.
layout(std430, binding = 0) readonly buffer In { float inp[]; };
// Per case: SVA_STAGE_WORDS words (the layout in the C++ test).
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
#define SVA_CASE_FLOATS 29u
#define SVA_STAGE_HEAD 26u
#define SVA_STAGE_WORDS (SVA_STAGE_HEAD + 5u * uint(SVA_MAX_BETA_SAMPLES))

SvaPatch patch_at(uint base) {
  SvaPatch p;
  p.p = vec3(inp[base], inp[base + 1u], inp[base + 2u]);
  p.n = vec3(inp[base + 3u], inp[base + 4u], inp[base + 5u]);
  p.conf = inp[base + 6u];
  return p;
}

void put(inout uint o, float x) { outp[o++] = floatBitsToUint(x); }
void put_u(inout uint o, uint x) { outp[o++] = x; }

void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= n) return;
  uint b = c * SVA_CASE_FLOATS;
  SvaAlignment al = sva_align(patch_at(b), patch_at(b + 7u), patch_at(b + 14u), patch_at(b + 21u));
  uint64_t units = sva_likelihood_units(inp[b + 28u]);
  units += sva_likelihood_units(inp[b + 6u] * inp[b + 20u] * inp[b + 28u]);
  float likelihood = sva_likelihood_of_units(units);
  SvaPoseGrid grid =
      sva_pose_grid(kind, translation_bins, translation_min, translation_width, rotation_bins, rotation_width);
  SvaBetaPlan plan = sva_beta_plan(al, grid);
  float sum = sva_beta_weight_sum(plan);
  float scale = sva_vote_scale(likelihood, sum);
  uint o = c * SVA_STAGE_WORDS;
  put(o, al.q1.x); put(o, al.q1.y); put(o, al.q1.z); put(o, al.q1.w);
  put(o, al.axis.x); put(o, al.axis.y); put(o, al.axis.z);
  put(o, al.c_obs.x); put(o, al.c_obs.y); put(o, al.c_obs.z);
  put(o, al.c_map_r.x); put(o, al.c_map_r.y); put(o, al.c_map_r.z);
  put(o, al.beta_hat); put(o, al.align_conf); put(o, al.sigma); put_u(o, uint(al.valid));
  put_u(o, uint(plan.n)); put_u(o, uint(plan.circle)); put(o, plan.unit); put(o, plan.inv_sigma);
  put(o, sum); put(o, scale);
  put_u(o, uint(units & 0xffffffffUL)); put_u(o, uint(units >> 32)); put(o, likelihood);
  for (int i = 0; i < SVA_MAX_BETA_SAMPLES; ++i) {
    if (i >= plan.n) break;
    precise float weight = sva_beta_weight(plan, i) * scale;
    SvaVote v = sva_vote(al, plan, grid, 1u, weight, i);
    put(o, weight);
    put_u(o, uint(v.key & 0xffffffffUL)); put_u(o, uint(v.key >> 32));
    put_u(o, uint(v.mass)); put_u(o, uint(v.inside));
  }
}
