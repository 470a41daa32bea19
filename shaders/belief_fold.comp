#version 460
// Folds every voted pair into its session's belief (Eq 3-5 in the log domain):
// offset(x) += log2(1 + S_p(x) / eps), with S_p the pair's votes over its
// total, computed from the integers by sva_fold_units exactly as the CPU
// reference does. One invocation per vote-table slot, in two passes:
//  RESERVE: add the slot's mass to its pair's total and insert the bin into
//           the session's table (a full table raises the session's overflow
//           flag: the host grows that table and folds the session again);
//  ADD:     add the slot's term to the reserved bin. Integer atomics, so the
//           order of the additions does not change the sums.
// Sessions whose `fold` is 0 are skipped (a rerun after a growth folds only
// the sessions that overflowed).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_hash.h"
#include "sva_belief_math.h"
#include "sva_gpu_layout.h"
#include "sva_belief_table.glsl"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer VoteKeys { uint64_t vote_key[]; };
layout(std430, set = 0, binding = 1) readonly buffer VoteSums { int64_t vote_sum[]; };
layout(std430, set = 0, binding = 2) readonly buffer Pairs { SvaGpuPair pairs[]; };
layout(std430, set = 0, binding = 3) buffer PairTotals { uint64_t pair_total[]; };
layout(std430, set = 0, binding = 4) readonly buffer Sessions { SvaGpuSession sessions[]; };
layout(std430, set = 0, binding = 5) buffer Status { SvaGpuSessionStatus status[]; };

layout(push_constant) uniform Push { SvaFoldParams pc; };

void main() {
  uint i = sva_flat_index();
  if (i >= pc.slots) return;
  uint64_t key = vote_key[i];
  if (key == SVA_HASH_EMPTY_KEY) return;
  int64_t mass = vote_sum[i];
  if (mass <= 0l) return;  // the scatter adds positive masses only; kept for safety
  uint64_t bins = uint64_t(pc.bins_lo) | (uint64_t(pc.bins_hi) << 32);
  uint64_t q = key / bins;
  uint64_t bin = key - q * bins;
  uint s = pairs[uint(q)].session;
  if (pc.pass == SVA_FOLD_RESERVE) atomicAdd(pair_total[uint(q)], uint64_t(mass));
  if (sessions[s].fold == 0u) return;
  SvaWords keys = sva_table_keys(sessions[s].table_lo, sessions[s].table_hi);
  uint capacity = sessions[s].capacity;
  if (pc.pass == SVA_FOLD_RESERVE) {
    atomicAdd(status[s].vote_entries, 1u);
    bool inserted;
    uint slot = sva_table_reserve(keys, capacity, bin, inserted);
    if (slot == capacity) atomicOr(status[s].overflow, 1u);
    else if (inserted) atomicAdd(status[s].inserted, 1u);
    return;
  }
  if (status[s].overflow != 0u) return;  // the session folds again after its table grows
  uint slot = sva_table_find(keys, capacity, bin);
  if (slot == capacity) {
    atomicOr(status[s].missing, 1u);
    return;
  }
  uint64_t eps_units = uint64_t(pc.eps_lo) | (uint64_t(pc.eps_hi) << 32);
  SvaWords offsets = sva_table_offsets(sessions[s].table_lo, sessions[s].table_hi, capacity);
  atomicAdd(offsets.w[slot], sva_fold_units(uint64_t(mass), pair_total[uint(q)], eps_units));
}
