#version 460
// The heavy loop of recognition on the GPU: one invocation per (observed pair
// key, map entry). The entry's map pair is voted by the first of the observed
// pair's keys that holds it (sva_match_likelihood.h), with the likelihood
// summed over all the keys that hold it (Eq 15): the invocation aligns the
// observed pair to the map pair (Sec 4.1, 4.3), samples the Gaussian in beta
// and scatters each sample's fixed-point vote into a hash table keyed by
// (pair, pose bin). The math is sva_vote_math.h, the same text the CPU
// reference compiles, so bins and integer sums agree bit for bit.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
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
layout(std430, set = 0, binding = 11) buffer PairCounters { uint64_t counters[]; };  // SVA_PAIR_COUNTERS per pair
layout(std430, set = 0, binding = 12) buffer Status { uint overflow; };
layout(std430, set = 0, binding = 13) readonly buffer Scan { SvaScanResult scan; };
layout(std430, set = 0, binding = 14) readonly buffer Chunks { SvaGpuChunk chunks[]; };

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer SvaU32s { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer SvaF32s { float v[]; };

layout(push_constant) uniform Push { SvaMatchParams pc; };

SvaPatch patch_of_reading(uint r) {
  SvaPatch p;
  p.p = vec3(readings[r].px, readings[r].py, readings[r].pz);
  p.n = vec3(readings[r].nx, readings[r].ny, readings[r].nz);
  p.conf = readings[r].conf;
  return p;
}

#include "sva_hash_scatter.glsl"

// Map entry i (global index) of any chunk, through the chunks' device addresses.
uint entry_a_at(uint i) {
  SvaGpuChunk c = chunks[i / pc.chunk_entries];
  return SvaU32s(uint64_t(c.a_lo) | (uint64_t(c.a_hi) << 32)).v[i % pc.chunk_entries];
}
uint entry_b_at(uint i) {
  SvaGpuChunk c = chunks[i / pc.chunk_entries];
  return SvaU32s(uint64_t(c.b_lo) | (uint64_t(c.b_hi) << 32)).v[i % pc.chunk_entries];
}
float entry_weight_at(uint i) {
  SvaGpuChunk c = chunks[i / pc.chunk_entries];
  return SvaF32s(uint64_t(c.w_lo) | (uint64_t(c.w_hi) << 32)).v[i % pc.chunk_entries];
}

// The entry of map pair (ra, rb) among the entries of key item k (sorted by
// (a, b)), or 0xffffffff when that key does not hold it.
uint find_entry(uint k, uint ra, uint rb) {
  uint lo = ranges[k].begin, hi = ranges[k].end;
  for (uint step = 0u; step < SVA_MAX_SEARCH_STEPS; ++step) {
    if (lo >= hi) break;
    uint mid = (lo + hi) >> 1;
    uint ma = entry_a_at(mid);
    if (ma < ra || (ma == ra && entry_b_at(mid) < rb)) lo = mid + 1u; else hi = mid;
  }
  if (lo < ranges[k].end && entry_a_at(lo) == ra && entry_b_at(lo) == rb) return lo;
  return 0xffffffffu;
}

// The likelihood units of the match of key item k at entry weight w: 0 when
// an earlier key item of the pair holds the same map pair (it votes it).
uint64_t owned_likelihood(uint q, uint k, uint ra, uint rb, float w) {
  for (uint i = pairs[q].item_begin; i < k; ++i)
    if (find_entry(i, ra, rb) != 0xffffffffu) return 0ul;
  uint64_t units = sva_likelihood_units(key_items[k].weight * w);
  for (uint i = k + 1u; i < pairs[q].item_end; ++i) {
    uint f = find_entry(i, ra, rb);
    if (f != 0xffffffffu) units += sva_likelihood_units(key_items[i].weight * entry_weight_at(f));
  }
  return units;
}

SvaPoseGrid pose_grid() {
  return sva_pose_grid(int(pc.grid_kind), pc.translation_bins, pc.translation_min, pc.translation_width,
                       pc.rotation_bins, pc.rotation_width);
}

void observed_patches(uint q, out SvaPatch a1, out SvaPatch b1) {
  a1.p = vec3(pairs[q].ax, pairs[q].ay, pairs[q].az);
  a1.n = vec3(pairs[q].anx, pairs[q].any, pairs[q].anz);
  a1.conf = pairs[q].aconf;
  b1.p = vec3(pairs[q].bx, pairs[q].by, pairs[q].bz);
  b1.n = vec3(pairs[q].bnx, pairs[q].bny, pairs[q].bnz);
  b1.conf = pairs[q].bconf;
}

// Aligns pair q to map pair (ra, rb) and scatters its beta samples.
void vote_match(uint q, uint ra, uint rb, uint object, float likelihood) {
  SvaPatch a1, b1;
  observed_patches(q, a1, b1);
  SvaPoseGrid grid = pose_grid();
  SvaAlignment al = sva_align(a1, b1, patch_of_reading(ra), patch_of_reading(rb));
  SvaBetaPlan plan = sva_beta_plan(al, grid);
  if (plan.n == 0) return;
  uint c = SVA_PAIR_COUNTERS * q;
  atomicAdd(counters[c], uint64_t(1));
  float scale = sva_vote_scale(likelihood, sva_beta_weight_sum(plan));
  uint64_t pair_base = uint64_t(q) << pc.pair_shift;
  uint inside = 0u, outside = 0u, zero = 0u;
  for (int s = 0; s < SVA_MAX_BETA_SAMPLES; ++s) {
    if (s >= plan.n) break;
    SvaVote v = sva_vote(al, plan, grid, object, scale, s);
    if (v.inside == 0) {
      ++outside;
      continue;
    }
    ++inside;
    if (v.mass > int64_t(0))
      sva_hash_scatter(pair_base | sva_linear_bin(v.key, uint(pc.translation_bins), uint(pc.rotation_bins), pc.dim_tz,
                                                  pc.dim_rxy, pc.object_shift),
                       v.mass, pc.capacity);
    else
      ++zero;
  }
  if (inside != 0u) atomicAdd(counters[c + 1u], uint64_t(inside));
  if (outside != 0u) atomicAdd(counters[c + 2u], uint64_t(outside));
  if (zero != 0u) atomicAdd(counters[c + 3u], uint64_t(zero));
}

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
  uint q = key_items[lo].pair;
  uint ra = entry_a[e];
  uint rb = entry_b[e];
  uint object = readings[ra].object;
  if (object_active[pairs[q].session * pc.objects + object] == 0u) return;
  precise float likelihood = sva_likelihood_of_units(owned_likelihood(q, lo, ra, rb, entry_weight[e]));
  if (!(likelihood > 0.0f) || likelihood < pc.likelihood_cutoff) return;
  vote_match(q, ra, rb, object, likelihood);
}
