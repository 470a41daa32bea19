#version 460
// Expands observed pairs' keys into map ranges: each key item (one
// (class a, class b, distance bin) key of one observed pair) finds its key in
// the map's sorted key array by a bounded binary search and writes the range of
// entries stored under it (empty when the map has no such key).
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_gpu_layout.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer KeyItems { SvaGpuKeyItem key_items[]; };
layout(std430, set = 0, binding = 1) readonly buffer MapKeys { uint map_keys[]; };
layout(std430, set = 0, binding = 2) readonly buffer MapOffsets { uint map_offsets[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Ranges { SvaGpuRange ranges[]; };

layout(push_constant) uniform Push { SvaExpandParams pc; };

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.key_items) return;
  uint key = key_items[k].key;
  // lower_bound over [0, map_keys)
  uint lo = 0u, hi = pc.map_keys;
  for (uint step = 0u; step < SVA_MAX_SEARCH_STEPS; ++step) {
    if (lo >= hi) break;
    uint mid = (lo + hi) >> 1;
    if (map_keys[mid] < key) lo = mid + 1u; else hi = mid;
  }
  SvaGpuRange r;
  r.begin = 0u;
  r.end = 0u;
  if (lo < pc.map_keys && map_keys[lo] == key) {
    r.begin = map_offsets[lo];
    r.end = map_offsets[lo + 1u];
  }
  ranges[k] = r;
}
