#version 460
// The estimate's reductions over one session's belief table, one invocation
// per slot, in three passes with the same integer results as the CPU
// reference's (host/src/recognition/belief.cpp):
//  MAX:    the largest offset M, and per object the touched bins and the
//          largest offset;
//  MASS:   per object the sum of 2^(offset - M) (sva_exp2_neg_units), the
//          smallest bin key holding the object's largest offset, and a
//          histogram of M - offset for choosing the top-k candidates;
//  SELECT: the bins whose distance bucket is at most select_bucket, appended
//          to the candidate list (the host sorts the few it gets).
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

layout(std430, set = 0, binding = 0) buffer Summary { uint64_t summary[]; };
layout(std430, set = 0, binding = 1) buffer Candidates { uint64_t candidate[]; };  // (key, offset) pairs

layout(push_constant) uniform Push { SvaReduceParams pc; };

void reduce_slot(uint i) {
  if (i >= pc.capacity) return;
  uint64_t key = sva_table_keys(pc.table_lo, pc.table_hi).w[i];
  if (key == SVA_HASH_EMPTY_KEY) return;
  uint64_t offset = sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[i];
  uint object = uint(key >> pc.object_shift);
  uint touched = SVA_SUMMARY_OBJECTS + object;
  uint mass = touched + pc.objects;
  uint best_offset = mass + pc.objects;
  uint best_key = best_offset + pc.objects;
  if (pc.pass == SVA_REDUCE_MAX) {
    atomicMax(summary[SVA_SUMMARY_MAX], offset);
    atomicAdd(summary[touched], 1ul);
    atomicMax(summary[best_offset], offset);
    return;
  }
  uint64_t d = summary[SVA_SUMMARY_MAX] - offset;
  uint bucket = sva_distance_bucket(d);
  if (pc.pass == SVA_REDUCE_MASS) {
    atomicAdd(summary[mass], sva_exp2_neg_units(d, pc.mass_bits));
    if (offset == summary[best_offset]) atomicMin(summary[best_key], key);
    atomicAdd(summary[SVA_SUMMARY_OBJECTS + 4u * pc.objects + bucket], 1ul);
    return;
  }
  if (bucket > pc.select_bucket) return;
  uint64_t n = atomicAdd(summary[SVA_SUMMARY_CANDIDATES], 1ul);
  if (n < uint64_t(pc.select_capacity)) {
    candidate[2u * uint(n)] = key;
    candidate[2u * uint(n) + 1u] = offset;
  }
}

void main() {
  for (uint k = 0u; k < SVA_SLOTS_PER_INVOCATION; ++k) reduce_slot(sva_table_slot(k));
}
