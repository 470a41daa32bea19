// A pose bin's neighbourhood, one text for the host's hypotheses (host/src/estimate/hypotheses.cpp, through
// host/src/votes/neighbourhood_steps.hpp) and the device's choice of the keys they read (belief_hoods.comp): the
// steps it takes along each grid axis and whether two bins lie within a radius of each other. Integers only, in the
// common subset of GLSL and C++ (min and abs from glm on the host).
#ifndef SVA_NEIGHBOURHOOD_H
#define SVA_NEIGHBOURHOOD_H

#ifdef __cplusplus
#define SVA_HOOD_FN inline
#else
#define SVA_HOOD_FN
#endif

// Axes 0-2 are the translation's, 3-5 the rotation's. A planar space steps tx, ty and its angle (axis 5) only; the
// angle goes round the circle, cut to distinct bins where the radius would go round it.
SVA_HOOD_FN bool sva_hood_axis_fixed(uint a, bool planar) { return planar && a >= 2u && a <= 4u; }

// The first and last step along axis a of a neighbourhood of `radius` grid steps, the grid's edges ignored.
SVA_HOOD_FN int sva_hood_step_lo(uint a, int radius, bool planar, int rotation_bins) {
  if (sva_hood_axis_fixed(a, planar)) return 0;
  return planar && a == 5u ? -min(radius, (rotation_bins - 1) / 2) : -radius;
}
SVA_HOOD_FN int sva_hood_step_hi(uint a, int radius, bool planar, int rotation_bins) {
  if (sva_hood_axis_fixed(a, planar)) return 0;
  return planar && a == 5u ? min(radius, rotation_bins - 1 - (rotation_bins - 1) / 2) : radius;
}

// Whether two bins whose indices differ by d along axis a lie within `radius` steps along it (the planar angle
// round the circle).
SVA_HOOD_FN bool sva_hood_axis_within(uint a, int d, int radius, bool planar, int rotation_bins) {
  int dist = abs(d);
  if (planar && a == 5u) dist = min(dist, rotation_bins - dist);
  return dist <= radius;
}

#endif
