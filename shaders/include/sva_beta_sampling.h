// Sampling the Gaussian in beta (paper Sec 4.3): how many samples a match
// casts, where they sit and what each weighs.
#ifndef SVA_BETA_SAMPLING_H
#define SVA_BETA_SAMPLING_H

#include "sva_pose_bins.h"

// Samples of beta per match: at most this many (odd, so that a narrow Gaussian
// is sampled at its mean). A uniform circle uses at most SVA_MAX_BETA_SAMPLES-1.
#define SVA_MAX_BETA_SAMPLES 65
// How finely beta is sampled, as samples per radian (the step's inverse): two per rotation bin, and two per
// translation bin at the lever arm of the map midpoint about the axis (rotating by beta moves the translation by
// |lever| * beta). From the grid's bins per radian and per mm, so that no exact division is needed (on a GPU each
// is an estimate and an integer correction, sva_div).
SVA_FN float sva_beta_density(SvaAlignment al, SvaPoseGrid grid) {
  SVA_PRECISE vec3 lever = al.c_map_r - sva_dot(al.c_map_r, al.axis) * al.axis;
  SVA_PRECISE float arm = max(sva_length(lever), 1.0e-3f);
  SVA_PRECISE float density = 2.0f * max(grid.rotation_scale, arm * grid.translation_scale);
  return density;
}

// How one match samples beta, worked out once per match so that each sample
// costs only multiplications. A Gaussian truncated at 3 sigma is sampled at
// 2m+1 points; once 3 sigma reaches pi, the whole circle is sampled evenly (a
// wrapped, then uniform, distribution), capped.
struct SvaBetaPlan {
  int n;            // samples (0: the match casts no vote)
  int circle;       // 1: even over the whole circle
  float unit;       // offset of sample i: unit * (2i + 1 - n) (circle) or unit * (i - (n-1)/2)
  float inv_sigma;  // 1 / sigma
};

SVA_FN SvaBetaPlan sva_beta_plan(SvaAlignment al, SvaPoseGrid grid) {
  // Written as selects (both plans worked out, one kept; an invalid alignment's plan is all zeros): the CPU plans a
  // block of matches in SIMD lanes (host/src/backends/cpu/align_lanes.cpp).
  SVA_PRECISE float density = sva_beta_density(al, grid);
  // 1 / sigma from alignConf itself (sigma = SIGMA_INIT / alignConf, floored): a product, not a division.
  SVA_PRECISE float inv_sigma = max(al.align_conf, SVA_MIN_ALIGN_CONF) * SVA_INV_SIGMA_INIT;
  bool circle = 3.0f * al.sigma >= SVA_PI;
  int n_circle = int(min(ceil(SVA_TWO_PI * density), float(SVA_MAX_BETA_SAMPLES - 1)));
  SVA_PRECISE float unit_circle = sva_div(SVA_PI, float(n_circle));
  SVA_PRECISE float h = 3.0f * al.sigma;
  SVA_PRECISE float m = min(ceil(h * density), float((SVA_MAX_BETA_SAMPLES - 1) / 2));
  int n_gaussian = 2 * int(m) + 1;
  SVA_PRECISE float unit_gaussian = m > 0.0f ? sva_div(h, m) : 0.0f;
  bool valid = al.valid != 0;
  SvaBetaPlan p;
  p.n = valid ? (circle ? n_circle : n_gaussian) : 0;
  p.circle = valid && circle ? 1 : 0;
  p.unit = valid ? (circle ? unit_circle : unit_gaussian) : 0.0f;
  p.inv_sigma = valid ? inv_sigma : 0.0f;
  return p;
}

// Offset from beta-hat of sample i, written as (signed integer) x (unit) so
// that sample n-1-i sits at exactly minus the offset of sample i. With the odd
// sva_sincos this makes the reversed observed pair, matched with the reversed
// map pair (axis -u, beta-hat -beta-hat, same R1 and midpoints), cast bit for
// bit the votes of the forward pair: Eq 5's two orders are folded from one
// vote (BayesFilter::queue_pairs).
SVA_FN float sva_beta_offset(SvaBetaPlan p, int i) {
  return p.unit * float(p.circle != 0 ? 2 * i + 1 - p.n : i - (p.n - 1) / 2);
}

// Unnormalised Gaussian weight of sample i.
SVA_FN float sva_beta_weight(SvaBetaPlan p, int i) {
  SVA_PRECISE float z = sva_beta_offset(p, i) * p.inv_sigma;
  return sva_exp_neg(-0.5f * z * z);
}

// The weights of all n samples into w, and their sum (votes are normalised
// per match), added in sample order. The CPU keeps the weights for its votes;
// the GPU only needs the sum (sva_beta_weight_sum; the compiler drops the
// unread array) and recomputes each weight where the sample is voted.
#ifdef __cplusplus
#define SVA_OUT_WEIGHTS(name) float (&name)[SVA_MAX_BETA_SAMPLES]
#else
#define SVA_OUT_WEIGHTS(name) out float name[SVA_MAX_BETA_SAMPLES]
#endif
SVA_FN float sva_beta_weights(SvaBetaPlan p, SVA_OUT_WEIGHTS(w)) {
  SVA_PRECISE float s = 0.0f;
  for (int i = 0; i < SVA_MAX_BETA_SAMPLES; ++i) {
    if (i >= p.n) break;
    w[i] = sva_beta_weight(p, i);
    s = s + w[i];
  }
  return s;
}

SVA_FN float sva_beta_weight_sum(SvaBetaPlan p) {
  float w[SVA_MAX_BETA_SAMPLES];
  return sva_beta_weights(p, w);
}

#endif
