// The per-match vote math of the SVA recognizer (paper Sec 4.1 and 4.3), written
// once for both the C++ reference backend and the GLSL compute backend. Split by
// concept: sva_fast_math.h, sva_quaternion.h, sva_alignment.h, sva_pose_bins.h,
// sva_beta_sampling.h; this file holds the vote of one beta sample.
//
// Why one text: the GPU backend must reproduce the CPU's pose bins and
// fixed-point masses bit for bit. So this file uses only the common subset of
// GLSL 4.60 and C++/glm, 32-bit float, and only + - * / sqrt floor ceil and
// comparisons; exp, sin, cos and atan2 are this file's own polynomials (libm and
// GPU builtins differ in their last bits). dot, cross and length are written
// out too, because a builtin dot may be evaluated in another order or fused.
//
// Rules for includers:
//  - include "sva_shared.h" first (SVA_TO_FIXED, fixed-point scale);
//  - GLSL: enable GL_EXT_shader_explicit_arithmetic_types_int64;
//  - C++: include inside a namespace after `using namespace glm;` with
//    std::int64_t / std::uint64_t visible as int64_t / uint64_t, and compile
//    with -ffp-contract=off (no fused multiply-add); see
//    host/src/votes/vote_math.hpp.
//  - GLSL: SVA_PRECISE expands to `precise` so that no driver fuses a*b+c.
//
// Rotations are unit quaternions vec4(x, y, z, w) = (sin(a/2) axis, cos(a/2)).
#ifndef SVA_VOTE_MATH_H
#define SVA_VOTE_MATH_H

#include "sva_beta_sampling.h"
#include "sva_match_likelihood.h"

// One beta sample's vote.
struct SvaVote {
  uint64_t key;
  int64_t mass;     // fixed point (SVA_TO_FIXED)
  int inside;       // 0: the pose lies outside the pose space (or is not planar)
};

// The mass scale of a match's samples: likelihood / sum_g (Eq 15 over the
// Gaussian's normaliser), once per match.
SVA_FN float sva_vote_scale(float likelihood, float weight_sum) { return sva_div(likelihood, weight_sum); }

// The vote of beta sample i of a match: pose bin and fixed-point mass
// `weight` = g_i * scale (Eq 15 times the normalised Gaussian in beta; the
// caller has g_i from the weight sum, sva_beta_weight). The translation is
// binned first: a sample outside the space needs no rotation.
SVA_FN SvaVote sva_vote(SvaAlignment al, SvaBetaPlan plan, SvaPoseGrid grid, uint object, float weight, int i) {
  SvaVote vote;
  vote.key = uint64_t(0);
  vote.mass = int64_t(0);
  vote.inside = 0;
  SVA_PRECISE float beta = al.beta_hat + sva_beta_offset(plan, i);
  SVA_PRECISE vec4 qb = sva_quat_axis_angle(al.axis, beta);
  SVA_PRECISE vec3 t = al.c_obs - sva_quat_rotate(qb, al.c_map_r);
  int tx = sva_translation_bin(t.x, grid);
  int ty = sva_translation_bin(t.y, grid);
  int tz = grid.kind == SVA_POSE_PLANAR ? 0 : sva_translation_bin(t.z, grid);
  if (tx < 0 || ty < 0 || tz < 0) return vote;
  SVA_PRECISE vec4 q = sva_quat_mul(qb, al.q1);
  int rx = 0;
  int ry = 0;
  int rz = 0;
  if (grid.kind == SVA_POSE_PLANAR) {
    if (sva_planar_tilted(q)) return vote;
    rz = sva_planar_rotation_bin(q, grid);
  } else {
    SVA_PRECISE vec3 r = sva_quat_to_rodrigues(q);
    rx = sva_rotation_bin(r.x, grid);
    ry = sva_rotation_bin(r.y, grid);
    rz = sva_rotation_bin(r.z, grid);
  }
  vote.key = sva_pack_bin_key(object, tx, ty, tz, rx, ry, rz);
  vote.mass = SVA_TO_FIXED(weight);
  vote.inside = 1;
  return vote;
}

#endif
