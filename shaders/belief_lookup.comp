#version 460
// Offsets of a few bins of one session's belief (0 for untouched bins): the
// neighbours of the best bin for the sub-bin refinement.
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

layout(std430, set = 0, binding = 0) buffer Queries { uint64_t query[]; };  // key in, offset out

layout(push_constant) uniform Push { SvaLookupParams pc; };

void main() {
  uint i = sva_flat_index();
  if (i >= pc.queries) return;
  uint slot = sva_table_find(sva_table_keys(pc.table_lo, pc.table_hi), pc.capacity, query[i]);
  query[i] = slot == pc.capacity ? 0ul : sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
}
