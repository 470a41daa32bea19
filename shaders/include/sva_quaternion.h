// Rotations of the shared vote math as unit quaternions vec4(x, y, z, w) =
// (sin(a/2) axis, cos(a/2)), with the canonical forms that make a pose bin
// unique: q and -q, and at an angle of pi r and -r, are one rotation.
#ifndef SVA_QUATERNION_H
#define SVA_QUATERNION_H

#include "sva_fast_math.h"

// Cosine below which two axes count as anti-parallel (180-degree branch of R1).
#define SVA_ANTIPARALLEL_COS -0.999999f
// |w| of the quaternion below which the rotation angle is pi up to float
// precision: r and -r are then the same rotation, so the sign is canonicalised.
#define SVA_NEAR_PI_W 1.0e-5f
// v or -v, whichever has its largest-magnitude component (ties to the earlier
// axis) positive: one representative of an axis whose sign carries no meaning.
SVA_FN vec3 sva_lead_positive(vec3 v) {
  SVA_PRECISE vec3 a = abs(v);
  float lead = v.x;
  lead = a.y > a.x && a.y >= a.z ? v.y : lead;
  lead = a.z > a.x && a.z > a.y ? v.z : lead;
  return lead < 0.0f ? -v : v;
}

SVA_FN vec4 sva_quat_mul(vec4 a, vec4 b) {
  SVA_PRECISE vec3 av = vec3(a.x, a.y, a.z);
  SVA_PRECISE vec3 bv = vec3(b.x, b.y, b.z);
  SVA_PRECISE vec3 c = sva_cross(av, bv);
  SVA_PRECISE vec3 v = a.w * bv + b.w * av + c;
  SVA_PRECISE float w = a.w * b.w - sva_dot(av, bv);
  return vec4(v.x, v.y, v.z, w);
}

// q * v * q^-1 for a unit quaternion: v + 2w (u x v) + 2 u x (u x v).
SVA_FN vec3 sva_quat_rotate(vec4 q, vec3 v) {
  SVA_PRECISE vec3 u = vec3(q.x, q.y, q.z);
  SVA_PRECISE vec3 t = 2.0f * sva_cross(u, v);
  SVA_PRECISE vec3 r = v + q.w * t + sva_cross(u, t);
  return r;
}

SVA_FN vec4 sva_quat_axis_angle(vec3 unit_axis, float angle) {
  SVA_PRECISE vec2 sc = sva_sincos(0.5f * angle);
  return vec4(sc.x * unit_axis.x, sc.x * unit_axis.y, sc.x * unit_axis.z, sc.y);
}

// The rotation taking unit vector `from` onto unit vector `to` by the shortest
// arc. Anti-parallel vectors have no unique shortest arc: take the half turn
// about the axis perpendicular to `from` built from its smallest component, a
// fixed rule so that CPU and GPU choose the same one (beta then fixes the rest).
// The axis's largest component is made positive, so (from, to) and
// (-from, -to) give the same quaternion, as they do off the branch. Both sides
// are computed and one kept (a select: the CPU aligns several matches in SIMD
// lanes, host/src/backends/cpu/align_lanes.cpp).
SVA_FN vec4 sva_quat_between(vec3 from, vec3 to) {
  SVA_PRECISE float c = sva_dot(from, to);
  SVA_PRECISE vec3 v = sva_cross(from, to);
  SVA_PRECISE vec4 q = vec4(v.x, v.y, v.z, 1.0f + c);
  SVA_PRECISE float l = sva_sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  SVA_PRECISE vec4 arc = q * sva_div(1.0f, l);  // one exact division, four products (as sva_normalize)
  SVA_PRECISE vec3 a = abs(from);
  vec3 e = vec3(1.0f, 0.0f, 0.0f);
  e = a.y < a.x && a.y <= a.z ? vec3(0.0f, 1.0f, 0.0f) : e;
  e = a.z < a.x && a.z < a.y ? vec3(0.0f, 0.0f, 1.0f) : e;
  SVA_PRECISE vec3 perp = sva_lead_positive(sva_normalize(sva_cross(from, e)));
  SVA_PRECISE vec4 half_turn = vec4(perp.x, perp.y, perp.z, 0.0f);
  return c > SVA_ANTIPARALLEL_COS ? arc : half_turn;
}

// 2 phi / sin(phi) for w = cos(phi) in [0, 1] (and a rounding above 1): the factor that turns a unit quaternion's
// vector part v = sin(phi) axis into its Rodrigues vector 2 phi axis. A polynomial in x = 1 - w, so that a sample's
// rotation costs no square root or division: those are what an exact result costs a GPU (sva_div, sva_sqrt), and
// the Rodrigues vector took three of them per sample (a length, atan2's quotient, angle / length), the most of any
// step of the vote math. The function is analytic on (-1, inf): its only singularity, at w = -1, sets the degree.
// Degree 10, interpolated at Chebyshev nodes on x in [0, 1]: 1.1e-7 from the exact value at worst, relative,
// evaluated in float (tests/votes/test_vote_math.cpp), so a Rodrigues vector moves by 1e-6 rad at most. The
// coefficients are floats written to 9 digits, so both languages read the same bits.
SVA_FN float sva_rodrigues_scale(float w) {
  SVA_PRECISE float x = 1.0f - w;
  SVA_PRECISE float p = 0.0145808356f;
  p = p * x - 0.0499806963f;
  p = p * x + 0.0870723575f;
  p = p * x - 0.0753621161f;
  p = p * x + 0.0575259402f;
  p = p * x + 0.00597995985f;
  p = p * x + 0.0546182804f;
  p = p * x + 0.113793395f;
  p = p * x + 0.266698837f;
  p = p * x + 0.666665852f;
  p = p * x + 2.0f;
  return p;
}

// Rodrigues vector (axis * angle, |r| <= pi up to rounding) of a unit quaternion. q and -q are the same rotation:
// take w >= 0. At an angle of pi (w ~ 0), r and -r are the same rotation too: make the largest-magnitude component
// positive. The angle comes from w alone (sva_rodrigues_scale), which assumes |q| = 1: a composition of unit
// quaternions is unit to a few units in the last place, which moves r by as little.
SVA_FN vec3 sva_quat_to_rodrigues(vec4 q) {
  bool flip = q.w < 0.0f;
  SVA_PRECISE vec3 v = flip ? -vec3(q.x, q.y, q.z) : vec3(q.x, q.y, q.z);
  SVA_PRECISE float w = flip ? -q.w : q.w;
  v = w < SVA_NEAR_PI_W ? sva_lead_positive(v) : v;
  SVA_PRECISE vec3 r = v * sva_rodrigues_scale(w);
  return r;
}

#endif
