// Alignment of a map pair (object frame) to an observed pair (robot frame),
// paper Sec 4.1 and 4.3: R1 takes the map pair's axis onto the observed one,
// beta-hat turns about it, and alignConf sets the spread sigma of beta.
#ifndef SVA_ALIGNMENT_H
#define SVA_ALIGNMENT_H

#include "sva_quaternion.h"

// Spread of beta for a fully confident alignment (paper Sec 4.3: 0.1 rad).
#define SVA_SIGMA_INIT 0.1f
#define SVA_INV_SIGMA_INIT 10.0f  // 1 / SVA_SIGMA_INIT
// alignConf below this counts as "no constraint": sigma = SIGMA_INIT / this is
// far wider than the circle, so the vote is (numerically) uniform in beta.
#define SVA_MIN_ALIGN_CONF 1.0e-4f
// Points closer than this (mm) define no axis: the pair is skipped.
#define SVA_MIN_PAIR_SEPARATION_MM 1.0e-3f

// One end of a pair: contact position, unit surface normal, normConf (Alg. 1).
struct SvaPatch {
  vec3 p;
  vec3 n;
  float conf;
};

// The alignment of a map pair (object frame) to an observed pair (robot frame):
// pose(beta) = (Rb(beta) * R1, c_obs - Rb(beta) * c_map_r), Rb about `axis`.
struct SvaAlignment {
  vec4 q1;          // R1: the map pair axis onto the observed pair axis
  vec3 axis;        // unit observed pair axis
  vec3 c_obs;       // observed pair midpoint
  vec3 c_map_r;     // R1 * map pair midpoint
  float beta_hat;   // Eq 16-18 (closed form, see sva_align)
  float align_conf; // Eq 19-21
  float sigma;      // sigma_init / alignConf (alignConf floored)
  int valid;        // 0: a pair's points coincide; no vote
};

// Sec 4.1 + 4.3: align map pair (a2, b2) onto observed pair (a1, b1).
// beta-hat: after R1, both pairs' normals are projected onto the plane normal
// to the observed axis; the rotation about the axis minimising
// sum_i |Rb pm_i - pn_i|^2 is the 2-D Procrustes solution
//   beta = atan2(sum_i axis . (pm_i x pn_i), sum_i pm_i . pn_i),
// which is what SVD of H = sum pm pn^T with the det < 0 reflection fix
// (Eq 16-18) yields when restricted to the plane: the projected vectors keep
// their lengths, so each end is weighted by |pm||pn| exactly as in H.
SVA_FN SvaAlignment sva_align(SvaPatch a1, SvaPatch b1, SvaPatch a2, SvaPatch b2) {
  SVA_PRECISE vec3 d1 = b1.p - a1.p;
  SVA_PRECISE vec3 d2 = b2.p - a2.p;
  SVA_PRECISE float l1 = sva_length(d1);
  SVA_PRECISE float l2 = sva_length(d2);
  // Written as selects (every value computed, the invalid case's kept where the points coincide): the CPU aligns
  // several matches in SIMD lanes (host/src/backends/cpu/align_lanes.cpp); the kept values are the same either way.
  bool valid = l1 >= SVA_MIN_PAIR_SEPARATION_MM && l2 >= SVA_MIN_PAIR_SEPARATION_MM;
  // One exact division per vector, and three products: on a GPU each division is an estimate and an integer
  // correction (sva_div), several times a product's cost.
  SVA_PRECISE vec3 u1 = d1 * sva_div(1.0f, l1);
  SVA_PRECISE vec3 u2 = d2 * sva_div(1.0f, l2);
  SVA_PRECISE vec4 q1 = sva_quat_between(u2, u1);
  SVA_PRECISE vec3 pn_a = a1.n - sva_dot(a1.n, u1) * u1;
  SVA_PRECISE vec3 pn_b = b1.n - sva_dot(b1.n, u1) * u1;
  SVA_PRECISE vec3 ma = sva_quat_rotate(q1, a2.n);
  SVA_PRECISE vec3 mb = sva_quat_rotate(q1, b2.n);
  SVA_PRECISE vec3 pm_a = ma - sva_dot(ma, u1) * u1;
  SVA_PRECISE vec3 pm_b = mb - sva_dot(mb, u1) * u1;
  SVA_PRECISE float s_cross = sva_dot(u1, sva_cross(pm_a, pn_a)) + sva_dot(u1, sva_cross(pm_b, pn_b));
  SVA_PRECISE float s_dot = sva_dot(pm_a, pn_a) + sva_dot(pm_b, pn_b);
  SVA_PRECISE float qa = sva_length(pn_a) * clamp(a1.conf, 0.0f, 1.0f) * sva_length(pm_a) * clamp(a2.conf, 0.0f, 1.0f);
  SVA_PRECISE float qb = sva_length(pn_b) * clamp(b1.conf, 0.0f, 1.0f) * sva_length(pm_b) * clamp(b2.conf, 0.0f, 1.0f);
  SVA_PRECISE float conf = 0.5f * (qa + qb);
  conf = conf >= 0.0f ? conf : 0.0f;  // NaN normals: no constraint
  SVA_PRECISE vec3 c1 = 0.5f * (a1.p + b1.p);
  SVA_PRECISE vec3 c2 = 0.5f * (a2.p + b2.p);
  SVA_PRECISE vec3 c_map_r = sva_quat_rotate(q1, c2);
  SVA_PRECISE float beta_hat = sva_atan2(s_cross, s_dot);
  SVA_PRECISE float sigma = sva_div(SVA_SIGMA_INIT, max(conf, SVA_MIN_ALIGN_CONF));
  SvaAlignment al;
  al.q1 = valid ? q1 : vec4(0.0f, 0.0f, 0.0f, 1.0f);
  al.axis = valid ? u1 : vec3(0.0f, 0.0f, 1.0f);
  al.c_obs = valid ? c1 : vec3(0.0f, 0.0f, 0.0f);
  al.c_map_r = valid ? c_map_r : vec3(0.0f, 0.0f, 0.0f);
  al.beta_hat = valid ? beta_hat : 0.0f;
  al.align_conf = valid ? conf : 0.0f;
  al.sigma = valid ? sigma : sva_div(SVA_SIGMA_INIT, SVA_MIN_ALIGN_CONF);
  al.valid = valid ? 1 : 0;
  return al;
}

#endif
