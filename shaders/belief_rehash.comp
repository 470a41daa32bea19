#version 460
// Moves every bin of a belief table into a larger one (the host grows a table
// before it can overflow, or after it did). One invocation per old slot; a
// key that finds no slot raises the overflow flag and the host grows more.
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

layout(push_constant) uniform Push { SvaRehashParams pc; };

void move_slot(uint i) {
  if (i >= pc.old_capacity) return;
  uint64_t key = sva_table_keys(pc.old_lo, pc.old_hi).w[i];
  if (key == SVA_HASH_EMPTY_KEY) return;
  uint64_t offset = sva_table_offsets(pc.old_lo, pc.old_hi, pc.old_capacity).w[i];
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
