// Sampling the Gaussian in beta (paper Sec 4.3): how many samples a match
// casts, where they sit and what each weighs.
#ifndef SVA_BETA_SAMPLING_H
#define SVA_BETA_SAMPLING_H

#include "sva_pose_bins.h"

// Samples of beta per match: at most this many (odd, so that a narrow Gaussian
// is sampled at its mean). A uniform circle uses at most SVA_MAX_BETA_SAMPLES-1.
#define SVA_MAX_BETA_SAMPLES 65
// How finely beta is sampled: half a rotation bin, and half a translation bin
// at the lever arm of the map midpoint about the axis (rotating by beta moves
// the translation by |lever| * beta).
SVA_FN float sva_beta_step(SvaAlignment al, SvaPoseGrid grid) {
  SVA_PRECISE vec3 lever = al.c_map_r - sva_dot(al.c_map_r, al.axis) * al.axis;
  SVA_PRECISE float arm = max(sva_length(lever), 1.0e-3f);
  return 0.5f * min(grid.rotation_width, grid.translation_width / arm);
}

// Number of beta samples. A Gaussian truncated at 3 sigma is sampled at
// 2m+1 points; once 3 sigma reaches pi, the whole circle is sampled evenly
// (a wrapped, then uniform, distribution), capped.
SVA_FN int sva_beta_sample_count(SvaAlignment al, SvaPoseGrid grid) {
  if (al.valid == 0) return 0;
  SVA_PRECISE float step = sva_beta_step(al, grid);
  if (3.0f * al.sigma >= SVA_PI) {
    return int(min(ceil(SVA_TWO_PI / step), float(SVA_MAX_BETA_SAMPLES - 1)));
  }
  SVA_PRECISE float m = min(ceil(3.0f * al.sigma / step), float((SVA_MAX_BETA_SAMPLES - 1) / 2));
  return 2 * int(m) + 1;
}

// Offset from beta-hat of sample i of n, written as (signed integer) x (step)
// so that sample n-1-i sits at exactly minus the offset of sample i. With the
// odd sva_sincos this makes the reversed observed pair, matched with the
// reversed map pair (axis -u, beta-hat -beta-hat, same R1 and midpoints), cast
// bit for bit the votes of the forward pair: Eq 5's two orders are folded from
// one vote (BayesFilter::queue_pairs).
SVA_FN float sva_beta_offset(SvaAlignment al, int i, int n) {
  if (3.0f * al.sigma >= SVA_PI) return SVA_PI * float(2 * i + 1 - n) / float(n);
  if (n <= 1) return 0.0f;
  int m = (n - 1) / 2;
  SVA_PRECISE float h = 3.0f * al.sigma;
  return h * float(i - m) / float(m);
}

// Unnormalised Gaussian weight of sample i.
SVA_FN float sva_beta_weight(SvaAlignment al, int i, int n) {
  SVA_PRECISE float z = sva_beta_offset(al, i, n) / al.sigma;
  return sva_exp_neg(-0.5f * z * z);
}

// Sum of the weights of all n samples: votes are normalised per match.
SVA_FN float sva_beta_weight_sum(SvaAlignment al, int n) {
  SVA_PRECISE float s = 0.0f;
  for (int i = 0; i < SVA_MAX_BETA_SAMPLES; ++i) {
    if (i >= n) break;
    s = s + sva_beta_weight(al, i, n);
  }
  return s;
}

#endif
