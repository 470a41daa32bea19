// The pose grid a match votes into and the 64-bit bin keys (object,
// translation bins, Rodrigues or planar angle bins) shared by every table.
#ifndef SVA_POSE_BINS_H
#define SVA_POSE_BINS_H

#include "sva_alignment.h"

// Planar pose space: samples whose rotation tilts the z axis by more than
// about 0.5 rad are not planar poses and are skipped: sin^2(0.25).
#define SVA_PLANAR_MAX_TILT_SIN2 0.0612087190f

#define SVA_POSE_SPATIAL 0
#define SVA_POSE_PLANAR 1

// Bin key layout (64 bits, 62 used): object | tx | ty | tz | rx | ry | rz.
#define SVA_KEY_RZ_SHIFT 0
#define SVA_KEY_RY_SHIFT 8
#define SVA_KEY_RX_SHIFT 16
#define SVA_KEY_TZ_SHIFT 24
#define SVA_KEY_TY_SHIFT 34
#define SVA_KEY_TX_SHIFT 44
#define SVA_KEY_OBJECT_SHIFT 54
#define SVA_KEY_ROT_BITS 8
#define SVA_KEY_TRANS_BITS 10
#define SVA_KEY_OBJECT_BITS 8
#define SVA_MAX_OBJECTS 255
#define SVA_MAX_TRANSLATION_BINS 1024
#define SVA_MAX_ROTATION_BINS 256

// The pose grid a match votes into (from PoseSpaceSpec).
struct SvaPoseGrid {
  int kind;                // SVA_POSE_SPATIAL or SVA_POSE_PLANAR
  int translation_bins;    // per axis (x, y, z; planar: x, y)
  float translation_min;   // mm
  float translation_width; // mm per bin
  int rotation_bins;       // per Rodrigues axis over [-pi, pi] (planar: the angle about z)
  float rotation_width;    // rad per bin
  float translation_scale; // bins per mm (1 / translation_width): binning multiplies, every sample
  float rotation_scale;    // bins per rad
};

// A grid with its scales: the one way both backends make it.
SVA_FN SvaPoseGrid sva_pose_grid(int kind, int translation_bins, float translation_min, float translation_width,
                                 int rotation_bins, float rotation_width) {
  SvaPoseGrid g;
  g.kind = kind;
  g.translation_bins = translation_bins;
  g.translation_min = translation_min;
  g.translation_width = translation_width;
  g.rotation_bins = rotation_bins;
  g.rotation_width = rotation_width;
  g.translation_scale = sva_div(1.0f, translation_width);
  g.rotation_scale = sva_div(1.0f, rotation_width);
  return g;
}

// Translation bin of one coordinate, or -1 outside the grid (NaN too).
SVA_FN int sva_translation_bin(float t, SvaPoseGrid grid) {
  SVA_PRECISE float f = (t - grid.translation_min) * grid.translation_scale;
  bool inside = f >= 0.0f && f < float(grid.translation_bins);
  int b = min(int(floor(inside ? f : 0.0f)), grid.translation_bins - 1);  // converts only a value inside the grid
  return inside ? b : -1;
}

// Rotation bin of one Rodrigues coordinate (or the planar angle) in [-pi, pi]; 0 below it (NaN too).
SVA_FN int sva_rotation_bin(float r, SvaPoseGrid grid) {
  SVA_PRECISE float f = (r + SVA_PI) * grid.rotation_scale;
  return min(int(floor(f >= 0.0f ? f : 0.0f)), grid.rotation_bins - 1);
}

// The planar pose space's rotation of a sample: the angle of q about z, and whether q tilts the z axis too far
// to be a planar pose at all (SVA_PLANAR_MAX_TILT_SIN2).
SVA_FN bool sva_planar_tilted(vec4 q) { return q.x * q.x + q.y * q.y > SVA_PLANAR_MAX_TILT_SIN2; }
SVA_FN int sva_planar_rotation_bin(vec4 q, SvaPoseGrid grid) {
  SVA_PRECISE float w = abs(q.w);
  SVA_PRECISE float sz = q.w < 0.0f ? -q.z : q.z;
  return sva_rotation_bin(2.0f * sva_atan2(sz, w), grid);
}

SVA_FN uint64_t sva_pack_bin_key(uint object, int tx, int ty, int tz, int rx, int ry, int rz) {
  return (uint64_t(object) << SVA_KEY_OBJECT_SHIFT) | (uint64_t(uint(tx)) << SVA_KEY_TX_SHIFT) |
         (uint64_t(uint(ty)) << SVA_KEY_TY_SHIFT) | (uint64_t(uint(tz)) << SVA_KEY_TZ_SHIFT) |
         (uint64_t(uint(rx)) << SVA_KEY_RX_SHIFT) | (uint64_t(uint(ry)) << SVA_KEY_RY_SHIFT) |
         (uint64_t(uint(rz)) << SVA_KEY_RZ_SHIFT);
}

// The GPU tables' index of a packed bin key (host/src/backends/vulkan/linear_bins.hpp):
// the object from bit object_shift up, below it one mixed-radix index over
// (tx, ty, tz, rx, ry, rz), with dim_tz = dim_rxy = 1 for planar spaces. Its
// order is the packed keys' order.
SVA_FN uint64_t sva_linear_bin(uint64_t key, uint translation_bins, uint rotation_bins, uint dim_tz, uint dim_rxy,
                               uint object_shift) {
  uint64_t trans = (uint64_t(1) << SVA_KEY_TRANS_BITS) - uint64_t(1);
  uint64_t rot = (uint64_t(1) << SVA_KEY_ROT_BITS) - uint64_t(1);
  uint64_t i = (key >> SVA_KEY_TX_SHIFT) & trans;
  i = i * uint64_t(translation_bins) + ((key >> SVA_KEY_TY_SHIFT) & trans);
  i = i * uint64_t(dim_tz) + ((key >> SVA_KEY_TZ_SHIFT) & trans);
  i = i * uint64_t(dim_rxy) + ((key >> SVA_KEY_RX_SHIFT) & rot);
  i = i * uint64_t(dim_rxy) + ((key >> SVA_KEY_RY_SHIFT) & rot);
  i = i * uint64_t(rotation_bins) + ((key >> SVA_KEY_RZ_SHIFT) & rot);
  return ((key >> SVA_KEY_OBJECT_SHIFT) << object_shift) | i;
}

#endif
