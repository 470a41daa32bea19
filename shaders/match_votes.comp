#version 460
// The heavy loop of recognition on the GPU: one invocation per (observed pair
// key, map entry) match. It evaluates the match likelihood (Eq 15), aligns the
// observed pair to the map pair (Sec 4.1, 4.3), samples the Gaussian in beta and
// scatters each sample's fixed-point vote into a hash table keyed by
// (pair, pose bin). The math is sva_vote_math.h, the same text the CPU
// reference compiles, so bins and integer sums agree bit for bit.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_hash.h"
#include "sva_vote_math.h"
#include "sva_gpu_layout.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer Pairs { SvaGpuPair pairs[]; };
layout(std430, set = 0, binding = 1) readonly buffer KeyItems { SvaGpuKeyItem key_items[]; };
layout(std430, set = 0, binding = 2) readonly buffer Ranges { SvaGpuRange ranges[]; };
layout(std430, set = 0, binding = 3) readonly buffer WorkOffsets { uint work_offset[]; };
layout(std430, set = 0, binding = 4) readonly buffer Readings { SvaGpuReading readings[]; };
layout(std430, set = 0, binding = 5) readonly buffer EntryA { uint entry_a[]; };
layout(std430, set = 0, binding = 6) readonly buffer EntryB { uint entry_b[]; };
layout(std430, set = 0, binding = 7) readonly buffer EntryWeight { float entry_weight[]; };
layout(std430, set = 0, binding = 8) readonly buffer ObjectActive { uint object_active[]; };
layout(std430, set = 0, binding = 9) buffer TableKeys { uint64_t table_key[]; };
layout(std430, set = 0, binding = 10) buffer TableSums { int64_t table_sum[]; };
layout(std430, set = 0, binding = 11) buffer PairCounters { uint64_t counters[]; };  // 3 per pair: matches, votes, outside
layout(std430, set = 0, binding = 12) buffer Status { uint overflow; };
layout(std430, set = 0, binding = 13) readonly buffer Scan { SvaScanResult scan; };

layout(push_constant) uniform Push { SvaMatchParams pc; };

SvaPatch patch_of_reading(uint r) {
  SvaPatch p;
  p.p = vec3(readings[r].px, readings[r].py, readings[r].pz);
  p.n = vec3(readings[r].nx, readings[r].ny, readings[r].nz);
  p.conf = readings[r].conf;
  return p;
}

#include "sva_hash_scatter.glsl"

void main() {
  // A 2-D indirect dispatch (x is capped at maxComputeWorkGroupCount[0]).
  uint w = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * SVA_WORKGROUP_SIZE + gl_LocalInvocationID.x;
  if (w >= scan.total) return;
  // The key item holding match w: the last k with work_offset[k] <= w (items
  // with no match in this chunk share their offset with the next one).
  uint lo = 0u, hi = pc.key_items;  // invariant: work_offset[lo] <= w < work_offset[hi]
  for (uint step = 0u; step < SVA_MAX_SEARCH_STEPS; ++step) {
    if (hi - lo <= 1u) break;
    uint mid = (lo + hi) >> 1;
    if (work_offset[mid] <= w) lo = mid; else hi = mid;
  }
  // Entry index within the bound chunk.
  uint e = max(ranges[lo].begin, pc.chunk_begin) - pc.chunk_begin + (w - work_offset[lo]);
  SvaGpuKeyItem ki = key_items[lo];
  uint q = ki.pair;
  uint ra = entry_a[e];
  uint rb = entry_b[e];
  uint object = readings[ra].object;
  uint session = pairs[q].session;
  if (object_active[session * pc.objects + object] == 0u) return;
  precise float likelihood = ki.weight * entry_weight[e];
  if (!(likelihood > 0.0f) || likelihood < pc.likelihood_cutoff) return;

  SvaPatch a1, b1;
  a1.p = vec3(pairs[q].ax, pairs[q].ay, pairs[q].az);
  a1.n = vec3(pairs[q].anx, pairs[q].any, pairs[q].anz);
  a1.conf = pairs[q].aconf;
  b1.p = vec3(pairs[q].bx, pairs[q].by, pairs[q].bz);
  b1.n = vec3(pairs[q].bnx, pairs[q].bny, pairs[q].bnz);
  b1.conf = pairs[q].bconf;
  SvaPoseGrid grid;
  grid.kind = int(pc.grid_kind);
  grid.translation_bins = pc.translation_bins;
  grid.translation_min = pc.translation_min;
  grid.translation_width = pc.translation_width;
  grid.rotation_bins = pc.rotation_bins;
  grid.rotation_width = pc.rotation_width;

  SvaAlignment al = sva_align(a1, b1, patch_of_reading(ra), patch_of_reading(rb));
  int n = sva_beta_sample_count(al, grid);
  if (n == 0) return;
  atomicAdd(counters[3u * q], uint64_t(1));
  float wsum = sva_beta_weight_sum(al, n);
  uint64_t pair_base = uint64_t(q) << pc.pair_shift;
  uint inside = 0u, outside = 0u;
  for (int s = 0; s < SVA_MAX_BETA_SAMPLES; ++s) {
    if (s >= n) break;
    SvaVote v = sva_vote(al, grid, object, likelihood, wsum, s, n);
    if (v.inside == 0) {
      ++outside;
      continue;
    }
    ++inside;
    if (v.mass > int64_t(0))
      sva_hash_scatter(pair_base | sva_linear_bin(v.key, uint(pc.translation_bins), uint(pc.rotation_bins), pc.dim_tz,
                                                  pc.dim_rxy, pc.object_shift),
                       v.mass, pc.capacity);
  }
  if (inside != 0u) atomicAdd(counters[3u * q + 1u], uint64_t(inside));
  if (outside != 0u) atomicAdd(counters[3u * q + 2u], uint64_t(outside));
}
