#version 460
// Moves every bin of a belief table into a larger one (the host grows a table
// before it can overflow, or after it did), or the bins a bounded belief keeps
// into a new one (`forget`: see BeliefState::forget_below). One invocation per
// old slot; a key that finds no slot raises the overflow flag and the host
// grows more.
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

layout(std430, set = 0, binding = 0) buffer Status { uint overflow; };
layout(std430, set = 0, binding = 1) readonly buffer Keep { uint64_t keep_key[]; };  // sorted


layout(push_constant) uniform Push { SvaRehashParams pc; };

bool kept(uint64_t key) {
  uint lo = 0u, hi = pc.keep_count;
  for (int step = 0; step < SVA_MAX_SEARCH_STEPS && lo < hi; ++step) {
    uint mid = lo + (hi - lo) / 2u;
    if (keep_key[mid] < key) lo = mid + 1u;
    else hi = mid;
  }
  return lo < pc.keep_count && keep_key[lo] == key;
}

void move_slot(uint i) {
  if (i >= pc.old_capacity) return;
  uint64_t key = sva_table_keys(pc.old_lo, pc.old_hi).w[i];
  if (key == SVA_HASH_EMPTY_KEY) return;
  uint64_t offset = sva_table_offsets(pc.old_lo, pc.old_hi, pc.old_capacity).w[i];
  if (pc.forget != 0u) {
    SvaWords state = SvaWords(sva_address(pc.state_lo, pc.state_hi));
    uint object = uint(key >> pc.object_shift);
    uint64_t keep = uint64_t(pc.keep_lo) | (uint64_t(pc.keep_hi) << 32);
    if (offset < keep && !kept(key)) return;
    atomicAdd(state.w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, object)], 1ul);
  }
  bool inserted;
  uint slot = sva_table_reserve(sva_table_keys(pc.new_lo, pc.new_hi), pc.new_capacity, key, inserted);
  if (slot == pc.new_capacity) {
    atomicOr(overflow, 1u);
    return;
  }
  sva_table_offsets(pc.new_lo, pc.new_hi, pc.new_capacity).w[slot] = offset;
}

void main() {
  for (uint k = 0u; k < SVA_SLOTS_PER_INVOCATION; ++k) move_slot(sva_table_slot(k));
}
