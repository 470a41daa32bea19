// The heavy loop of recognition on the GPU (included by match_votes.comp and
// match_votes_portable.comp). A workgroup takes SVA_WORKGROUP_SIZE (observed
// pair key, map entry) work items. Phase 1, one invocation per item: the
// entry's map pair is voted by the first of the observed pair's keys that holds
// it (sva_match_likelihood.h), with the likelihood summed over all the keys
// that hold it (Eq 15); the owner aligns the observed pair to the map pair
// (Sec 4.1, 4.3) and plans its beta samples into shared memory. Phase 2: the
// workgroup's samples, all matches together, are dealt out to its invocations,
// so that a narrow Gaussian of 1 sample and a full circle of 64 do not leave
// lanes idle; each sample's fixed-point vote goes into the hash table keyed by
// (pair, pose bin), after neighbouring lanes with the same key have summed
// their masses (subgroup pre-aggregation, where the device has it). The math
// is sva_vote_math.h, the same text the CPU reference compiles, and the sums
// are integers: bins and sums agree bit for bit with the CPU, in any order.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#ifdef SVA_SUBGROUP_AGGREGATION
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
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

// Phase 1's plans, per invocation of the workgroup.
shared SvaAlignment s_al[SVA_WORKGROUP_SIZE];
shared SvaBetaPlan s_plan[SVA_WORKGROUP_SIZE];
shared float s_scale[SVA_WORKGROUP_SIZE];
shared uint s_object[SVA_WORKGROUP_SIZE];
shared uint s_pair[SVA_WORKGROUP_SIZE];
shared uint s_first[SVA_WORKGROUP_SIZE + 1];  // first sample of each plan among the workgroup's
shared uint s_inside[SVA_WORKGROUP_SIZE];
shared uint s_outside[SVA_WORKGROUP_SIZE];
shared uint s_zero[SVA_WORKGROUP_SIZE];
shared uint s_adds[SVA_WORKGROUP_SIZE];    // the vote table's atomic adds of each plan's votes
shared uint s_probes[SVA_WORKGROUP_SIZE];  // and its compare-and-swaps

SvaPatch patch_of_reading(uint r) {
  SvaPatch p;
  p.p = vec3(readings[r].px, readings[r].py, readings[r].pz);
  p.n = vec3(readings[r].nx, readings[r].ny, readings[r].nz);
  p.conf = readings[r].conf;
  return p;
}

#include "sva_hash_scatter.glsl"

// Map entry i (global index) of any chunk, through the chunks' device addresses. A chunk holds a power of two of
// entries, so the owner rule's searches (several reads per step) shift and mask where a division by a value known
// only at run time cost a GPU some twenty instructions per read.
uint sva_entry_in_chunk(uint i) { return i & ((1u << pc.chunk_shift) - 1u); }
uint sva_entry_a(uint i) {
  SvaGpuChunk c = chunks[i >> pc.chunk_shift];
  return SvaU32s(uint64_t(c.a_lo) | (uint64_t(c.a_hi) << 32)).v[sva_entry_in_chunk(i)];
}
uint sva_entry_b(uint i) {
  SvaGpuChunk c = chunks[i >> pc.chunk_shift];
  return SvaU32s(uint64_t(c.b_lo) | (uint64_t(c.b_hi) << 32)).v[sva_entry_in_chunk(i)];
}
float sva_entry_weight(uint i) {
  SvaGpuChunk c = chunks[i >> pc.chunk_shift];
  return SvaF32s(uint64_t(c.w_lo) | (uint64_t(c.w_hi) << 32)).v[sva_entry_in_chunk(i)];
}
// Key item k: its map range (expand_pair_keys.comp), orientation and weight.
uint sva_item_begin(uint k) { return ranges[k].begin; }
uint sva_item_end(uint k) { return ranges[k].end; }
uint sva_item_reversed(uint k) { return key_items[k].reversed; }
float sva_item_weight(uint k) { return key_items[k].weight; }

#include "sva_match_owner.h"

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

// Phase 1 for work item w: the plan of the match it owns (n = 0 when none).
void plan_item(uint w, uint lid) {
  SvaBetaPlan plan;
  plan.n = 0;
  plan.circle = 0;
  plan.unit = 0.0f;
  plan.inv_sigma = 0.0f;
  s_plan[lid] = plan;
  s_inside[lid] = 0u;
  s_outside[lid] = 0u;
  s_zero[lid] = 0u;
  s_adds[lid] = 0u;
  s_probes[lid] = 0u;
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
  bool reversed = key_items[lo].reversed != 0u;  // the entry's ends swapped to match the observed pair
  uint ra = reversed ? entry_b[e] : entry_a[e];
  uint rb = reversed ? entry_a[e] : entry_b[e];
  uint object = readings[ra].object;
  if (object_active[pairs[q].session * pc.objects + object] == 0u) return;
  precise float likelihood =
      sva_likelihood_of_units(sva_owned_likelihood(pairs[q].item_begin, lo, pairs[q].item_end, ra, rb, entry_weight[e]));
  if (!(likelihood > 0.0f) || likelihood < pc.likelihood_cutoff) return;
  SvaPatch a1, b1;
  observed_patches(q, a1, b1);
  SvaAlignment al = sva_align(a1, b1, patch_of_reading(ra), patch_of_reading(rb));
  plan = sva_beta_plan(al, pose_grid());
  if (plan.n == 0) return;
  atomicAdd(counters[SVA_PAIR_COUNTERS * q], uint64_t(1));
  s_al[lid] = al;
  s_plan[lid] = plan;
  s_scale[lid] = sva_vote_scale(likelihood, sva_beta_weight_sum(plan));
  s_object[lid] = object;
  s_pair[lid] = q;
}

// Scatters one vote per lane that has one. With subgroup operations, the lanes
// holding one key add their masses and one of them scatters the sum: samples
// dealt out in order put neighbouring samples of a match, which often share a
// bin, in neighbouring lanes. Every lane's mass is added exactly once whatever
// the device's reconvergence: a lane leaves only in the round whose sum it
// joined. A vote is at most 2^24 units, so a subgroup's sum fits 32 bits.
// The atomics are counted against plan `lo` of the lane that scatters.
void count_scatter(uint lo, uint probes) {
  atomicAdd(s_adds[lo], 1u);
  atomicAdd(s_probes[lo], probes);
}

void scatter_vote(bool has_vote, uint64_t key, int64_t mass, uint lo) {
#ifdef SVA_SUBGROUP_AGGREGATION
  bool pending = has_vote;
  uint key_lo = uint(key & 0xffffffffUL), key_hi = uint(key >> 32);
  for (uint round = 0u; round < 128u; ++round) {  // each round retires at least one lane
    if (!subgroupAny(pending)) break;
    if (pending) {
      uint lead_lo = subgroupBroadcastFirst(key_lo);
      uint lead_hi = subgroupBroadcastFirst(key_hi);
      if (lead_lo == key_lo && lead_hi == key_hi) {
        uint sum = subgroupAdd(uint(mass));
        if (subgroupElect()) count_scatter(lo, sva_hash_scatter(key, int64_t(sum), pc.capacity));
        pending = false;
      }
    }
  }
#else
  if (has_vote) count_scatter(lo, sva_hash_scatter(key, mass, pc.capacity));
#endif
}

// Phase 2: sample t of the workgroup's samples; its plan is the last m with s_first[m] <= t.
void vote_sample(uint t, SvaPoseGrid grid) {
  bool has_vote = false;
  uint64_t key = 0ul;
  int64_t mass = 0l;
  uint lo = 0u;
  if (t < s_first[SVA_WORKGROUP_SIZE]) {
    uint hi = SVA_WORKGROUP_SIZE;  // invariant: s_first[lo] <= t < s_first[hi]
    for (uint step = 0u; step < 8u; ++step) {
      if (hi - lo <= 1u) break;
      uint mid = (lo + hi) >> 1;
      if (s_first[mid] <= t) lo = mid; else hi = mid;
    }
    int i = int(t - s_first[lo]);
    precise float weight = sva_beta_weight(s_plan[lo], i) * s_scale[lo];
    SvaVote v = sva_vote(s_al[lo], s_plan[lo], grid, s_object[lo], weight, i);
    if (v.inside == 0) {
      atomicAdd(s_outside[lo], 1u);
    } else if (v.mass > 0l) {
      atomicAdd(s_inside[lo], 1u);
      has_vote = true;
      mass = v.mass;
      key = (uint64_t(s_pair[lo]) << pc.pair_shift) |
            sva_linear_bin(v.key, uint(pc.translation_bins), uint(pc.rotation_bins), pc.dim_tz, pc.dim_rxy,
                           pc.object_shift);
    } else {
      atomicAdd(s_inside[lo], 1u);
      atomicAdd(s_zero[lo], 1u);
    }
  }
  scatter_vote(has_vote, key, mass, lo);
}

void main() {
  // A 2-D indirect dispatch (x is capped at maxComputeWorkGroupCount[0]).
  uint lid = gl_LocalInvocationID.x;
  uint w = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * SVA_WORKGROUP_SIZE + lid;
  plan_item(w, lid);
  barrier();
  if (lid == 0u) {
    uint first = 0u;
    for (uint i = 0u; i < SVA_WORKGROUP_SIZE; ++i) {
      s_first[i] = first;
      first += uint(s_plan[i].n);
    }
    s_first[SVA_WORKGROUP_SIZE] = first;
  }
  barrier();
  SvaPoseGrid grid = pose_grid();
  uint total = s_first[SVA_WORKGROUP_SIZE];
  // Uniform rounds (every invocation runs each), so subgroups stay whole.
  for (uint round = 0u; round < uint(SVA_MAX_BETA_SAMPLES); ++round) {
    uint base = round * SVA_WORKGROUP_SIZE;
    if (base >= total) break;
    vote_sample(base + lid, grid);
  }
  barrier();
  if (s_plan[lid].n > 0) {
    uint c = SVA_PAIR_COUNTERS * s_pair[lid];
    if (s_inside[lid] != 0u) atomicAdd(counters[c + 1u], uint64_t(s_inside[lid]));
    if (s_outside[lid] != 0u) atomicAdd(counters[c + 2u], uint64_t(s_outside[lid]));
    if (s_zero[lid] != 0u) atomicAdd(counters[c + 3u], uint64_t(s_zero[lid]));
    if (s_adds[lid] != 0u) atomicAdd(counters[c + 4u], uint64_t(s_adds[lid]));
    if (s_probes[lid] != 0u) atomicAdd(counters[c + 5u], uint64_t(s_probes[lid]));
  }
}
