// The per-match vote math of the SVA recognizer (paper Sec 4.1 and 4.3), written
// once for both the C++ reference backend and the GLSL compute backend.
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
//    host/src/recognition/vote_math.hpp.
//  - GLSL: SVA_PRECISE expands to `precise` so that no driver fuses a*b+c.
//
// Rotations are unit quaternions vec4(x, y, z, w) = (sin(a/2) axis, cos(a/2)).
#ifndef SVA_VOTE_MATH_H
#define SVA_VOTE_MATH_H

#ifdef __cplusplus
#define SVA_PRECISE
#define SVA_FN inline
#else
#define SVA_PRECISE precise
#define SVA_FN
#endif

#define SVA_PI 3.14159265358979f
#define SVA_TWO_PI 6.28318530717959f
#define SVA_HALF_PI 1.57079632679490f
#define SVA_QUARTER_PI 0.785398163397448f
#define SVA_LN2 0.693147180559945f

// Spread of beta for a fully confident alignment (paper Sec 4.3: 0.1 rad).
#define SVA_SIGMA_INIT 0.1f
// alignConf below this counts as "no constraint": sigma = SIGMA_INIT / this is
// far wider than the circle, so the vote is (numerically) uniform in beta.
#define SVA_MIN_ALIGN_CONF 1.0e-4f
// Samples of beta per match: at most this many (odd, so that a narrow Gaussian
// is sampled at its mean). A uniform circle uses at most SVA_MAX_BETA_SAMPLES-1.
#define SVA_MAX_BETA_SAMPLES 65
// Points closer than this (mm) define no axis: the pair is skipped.
#define SVA_MIN_PAIR_SEPARATION_MM 1.0e-3f
// Cosine below which two axes count as anti-parallel (180-degree branch of R1).
#define SVA_ANTIPARALLEL_COS -0.999999f
// |w| of the quaternion below which the rotation angle is pi up to float
// precision: r and -r are then the same rotation, so the sign is canonicalised.
#define SVA_NEAR_PI_W 1.0e-5f
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
};

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

// One beta sample's vote.
struct SvaVote {
  uint64_t key;
  int64_t mass;     // fixed point (SVA_TO_FIXED)
  int inside;       // 0: the pose lies outside the pose space (or is not planar)
};

SVA_FN float sva_dot(vec3 a, vec3 b) {
  SVA_PRECISE float d = a.x * b.x + a.y * b.y + a.z * b.z;
  return d;
}

SVA_FN vec3 sva_cross(vec3 a, vec3 b) {
  SVA_PRECISE vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  return c;
}

SVA_FN float sva_length(vec3 a) { return sqrt(sva_dot(a, a)); }

// exp(x) for x <= 0 (Gaussian weights); x below -80 gives 0. Range reduction
// x = k ln2 + r, |r| <= ln2/2, Taylor to degree 8 (error < 1e-8 relative),
// then k exact halvings.
SVA_FN float sva_exp_neg(float x) {
  if (!(x > -80.0f)) return 0.0f;
  if (x > 0.0f) x = 0.0f;
  SVA_PRECISE float kf = floor(x / SVA_LN2 + 0.5f);
  SVA_PRECISE float r = x - kf * SVA_LN2;
  SVA_PRECISE float e =
      1.0f + r * (1.0f + r * (0.5f + r * (1.0f / 6.0f + r * (1.0f / 24.0f + r * (1.0f / 120.0f + r * (1.0f / 720.0f + r * (1.0f / 5040.0f + r * (1.0f / 40320.0f))))))));
  int k = int(-kf);
  for (int i = 0; i < 128; ++i) {
    if (i >= k) break;
    e = e * 0.5f;
  }
  return e;
}

// atan(t) for 0 <= t <= 1: above tan(pi/8) use atan(t) = pi/4 + atan((t-1)/(t+1)),
// so the alternating Taylor series runs on |u| <= 0.4143; terms to u^15 leave
// an error below 1e-7.
SVA_FN float sva_atan01(float t) {
  SVA_PRECISE float base = 0.0f;
  SVA_PRECISE float u = t;
  if (t > 0.41421356f) {
    base = SVA_QUARTER_PI;
    u = (t - 1.0f) / (t + 1.0f);
  }
  SVA_PRECISE float u2 = u * u;
  SVA_PRECISE float s = u * (1.0f + u2 * (-1.0f / 3.0f + u2 * (1.0f / 5.0f + u2 * (-1.0f / 7.0f + u2 * (1.0f / 9.0f + u2 * (-1.0f / 11.0f + u2 * (1.0f / 13.0f + u2 * (-1.0f / 15.0f))))))));
  return base + s;
}

// atan2(y, x) in [-pi, pi]; atan2(0, 0) = 0.
SVA_FN float sva_atan2(float y, float x) {
  SVA_PRECISE float ax = abs(x);
  SVA_PRECISE float ay = abs(y);
  SVA_PRECISE float hi = max(ax, ay);
  if (!(hi > 0.0f)) return 0.0f;
  SVA_PRECISE float lo = min(ax, ay);
  SVA_PRECISE float a = sva_atan01(lo / hi);
  if (ay > ax) a = SVA_HALF_PI - a;
  if (x < 0.0f) a = SVA_PI - a;
  if (y < 0.0f) a = -a;
  return a;
}

// vec2(sin x, cos x). x is reduced to [-pi, pi), halved (|h| <= pi/2, where the
// Taylor series to h^13 / h^14 err below 1e-9) and doubled back.
SVA_FN vec2 sva_sincos(float x) {
  SVA_PRECISE float xr = x - SVA_TWO_PI * floor((x + SVA_PI) / SVA_TWO_PI);
  SVA_PRECISE float h = 0.5f * xr;
  SVA_PRECISE float h2 = h * h;
  SVA_PRECISE float sh = h * (1.0f + h2 * (-1.0f / 6.0f + h2 * (1.0f / 120.0f + h2 * (-1.0f / 5040.0f + h2 * (1.0f / 362880.0f + h2 * (-1.0f / 39916800.0f + h2 * (1.0f / 6227020800.0f)))))));
  SVA_PRECISE float ch = 1.0f + h2 * (-0.5f + h2 * (1.0f / 24.0f + h2 * (-1.0f / 720.0f + h2 * (1.0f / 40320.0f + h2 * (-1.0f / 3628800.0f + h2 * (1.0f / 479001600.0f + h2 * (-1.0f / 87178291200.0f)))))));
  SVA_PRECISE float s = 2.0f * sh * ch;
  SVA_PRECISE float c = 1.0f - 2.0f * sh * sh;
  return vec2(s, c);
}

SVA_FN vec3 sva_normalize(vec3 v) {
  SVA_PRECISE float l = sva_length(v);
  if (!(l > 0.0f)) return vec3(0.0f, 0.0f, 0.0f);
  return v / l;
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
SVA_FN vec4 sva_quat_between(vec3 from, vec3 to) {
  SVA_PRECISE float c = sva_dot(from, to);
  if (c > SVA_ANTIPARALLEL_COS) {
    SVA_PRECISE vec3 v = sva_cross(from, to);
    SVA_PRECISE vec4 q = vec4(v.x, v.y, v.z, 1.0f + c);
    SVA_PRECISE float l = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return q / l;
  }
  SVA_PRECISE vec3 a = abs(from);
  vec3 e = vec3(1.0f, 0.0f, 0.0f);
  if (a.y < a.x && a.y <= a.z) e = vec3(0.0f, 1.0f, 0.0f);
  if (a.z < a.x && a.z < a.y) e = vec3(0.0f, 0.0f, 1.0f);
  SVA_PRECISE vec3 perp = sva_normalize(sva_cross(from, e));
  return vec4(perp.x, perp.y, perp.z, 0.0f);
}

// Rodrigues vector (axis * angle, |r| <= pi) of a unit quaternion. q and -q are
// the same rotation: take w >= 0. At an angle of pi (w ~ 0), r and -r are the
// same rotation too: make the largest-magnitude component positive.
SVA_FN vec3 sva_quat_to_rodrigues(vec4 q) {
  SVA_PRECISE vec3 v = vec3(q.x, q.y, q.z);
  SVA_PRECISE float w = q.w;
  if (w < 0.0f) {
    v = -v;
    w = -w;
  }
  if (w < SVA_NEAR_PI_W) {
    SVA_PRECISE vec3 a = abs(v);
    float lead = v.x;
    if (a.y > a.x && a.y >= a.z) lead = v.y;
    if (a.z > a.x && a.z > a.y) lead = v.z;
    if (lead < 0.0f) v = -v;
  }
  SVA_PRECISE float s = sva_length(v);
  if (!(s > 0.0f)) return vec3(0.0f, 0.0f, 0.0f);
  SVA_PRECISE float angle = 2.0f * sva_atan2(s, w);
  return v * (angle / s);
}

// Sec 4.1 + 4.3: align map pair (a2, b2) onto observed pair (a1, b1).
// beta-hat: after R1, both pairs' normals are projected onto the plane normal
// to the observed axis; the rotation about the axis minimising
// sum_i |Rb pm_i - pn_i|^2 is the 2-D Procrustes solution
//   beta = atan2(sum_i axis . (pm_i x pn_i), sum_i pm_i . pn_i),
// which is what SVD of H = sum pm pn^T with the det < 0 reflection fix
// (Eq 16-18) yields when restricted to the plane: the projected vectors keep
// their lengths, so each end is weighted by |pm||pn| exactly as in H.
SVA_FN SvaAlignment sva_align(SvaPatch a1, SvaPatch b1, SvaPatch a2, SvaPatch b2) {
  SvaAlignment al;
  al.q1 = vec4(0.0f, 0.0f, 0.0f, 1.0f);
  al.axis = vec3(0.0f, 0.0f, 1.0f);
  al.c_obs = vec3(0.0f, 0.0f, 0.0f);
  al.c_map_r = vec3(0.0f, 0.0f, 0.0f);
  al.beta_hat = 0.0f;
  al.align_conf = 0.0f;
  al.sigma = SVA_SIGMA_INIT / SVA_MIN_ALIGN_CONF;
  al.valid = 0;
  SVA_PRECISE vec3 d1 = b1.p - a1.p;
  SVA_PRECISE vec3 d2 = b2.p - a2.p;
  SVA_PRECISE float l1 = sva_length(d1);
  SVA_PRECISE float l2 = sva_length(d2);
  if (!(l1 >= SVA_MIN_PAIR_SEPARATION_MM) || !(l2 >= SVA_MIN_PAIR_SEPARATION_MM)) return al;
  SVA_PRECISE vec3 u1 = d1 / l1;
  SVA_PRECISE vec3 u2 = d2 / l2;
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
  if (!(conf >= 0.0f)) conf = 0.0f;  // NaN normals: no constraint
  SVA_PRECISE vec3 c1 = 0.5f * (a1.p + b1.p);
  SVA_PRECISE vec3 c2 = 0.5f * (a2.p + b2.p);
  al.q1 = q1;
  al.axis = u1;
  al.c_obs = c1;
  al.c_map_r = sva_quat_rotate(q1, c2);
  al.beta_hat = sva_atan2(s_cross, s_dot);
  al.align_conf = conf;
  al.sigma = SVA_SIGMA_INIT / max(conf, SVA_MIN_ALIGN_CONF);
  al.valid = 1;
  return al;
}

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

// Offset from beta-hat of sample i of n.
SVA_FN float sva_beta_offset(SvaAlignment al, int i, int n) {
  if (3.0f * al.sigma >= SVA_PI) return -SVA_PI + SVA_TWO_PI * (float(i) + 0.5f) / float(n);
  if (n <= 1) return 0.0f;
  SVA_PRECISE float h = 3.0f * al.sigma;
  return -h + 2.0f * h * float(i) / float(n - 1);
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

// Translation bin of one coordinate, or -1 outside the grid (NaN too).
SVA_FN int sva_translation_bin(float t, SvaPoseGrid grid) {
  SVA_PRECISE float f = (t - grid.translation_min) / grid.translation_width;
  if (!(f >= 0.0f) || !(f < float(grid.translation_bins))) return -1;
  return min(int(floor(f)), grid.translation_bins - 1);
}

// Rotation bin of one Rodrigues coordinate (or the planar angle) in [-pi, pi].
SVA_FN int sva_rotation_bin(float r, SvaPoseGrid grid) {
  SVA_PRECISE float f = (r + SVA_PI) / grid.rotation_width;
  if (!(f >= 0.0f)) return 0;  // also NaN; callers never pass NaN
  return min(int(floor(f)), grid.rotation_bins - 1);
}

SVA_FN uint64_t sva_pack_bin_key(uint object, int tx, int ty, int tz, int rx, int ry, int rz) {
  return (uint64_t(object) << SVA_KEY_OBJECT_SHIFT) | (uint64_t(uint(tx)) << SVA_KEY_TX_SHIFT) |
         (uint64_t(uint(ty)) << SVA_KEY_TY_SHIFT) | (uint64_t(uint(tz)) << SVA_KEY_TZ_SHIFT) |
         (uint64_t(uint(rx)) << SVA_KEY_RX_SHIFT) | (uint64_t(uint(ry)) << SVA_KEY_RY_SHIFT) |
         (uint64_t(uint(rz)) << SVA_KEY_RZ_SHIFT);
}

// The GPU tables' index of a packed bin key (host/src/vulkan/linear_bins.hpp):
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

// The vote of beta sample i of n: pose bin and fixed-point mass
// likelihood * g_i / sum_g (Eq 15 times the normalised Gaussian in beta).
SVA_FN SvaVote sva_vote(SvaAlignment al, SvaPoseGrid grid, uint object, float likelihood, float weight_sum, int i, int n) {
  SvaVote vote;
  vote.key = uint64_t(0);
  vote.mass = int64_t(0);
  vote.inside = 0;
  SVA_PRECISE float beta = al.beta_hat + sva_beta_offset(al, i, n);
  SVA_PRECISE vec4 qb = sva_quat_axis_angle(al.axis, beta);
  SVA_PRECISE vec4 q = sva_quat_mul(qb, al.q1);
  SVA_PRECISE vec3 t = al.c_obs - sva_quat_rotate(qb, al.c_map_r);
  int tx = sva_translation_bin(t.x, grid);
  int ty = sva_translation_bin(t.y, grid);
  int tz = 0;
  int rx = 0;
  int ry = 0;
  int rz = 0;
  if (grid.kind == SVA_POSE_PLANAR) {
    SVA_PRECISE float w = abs(q.w);
    SVA_PRECISE float sz = q.w < 0.0f ? -q.z : q.z;
    if (q.x * q.x + q.y * q.y > SVA_PLANAR_MAX_TILT_SIN2) return vote;
    rz = sva_rotation_bin(2.0f * sva_atan2(sz, w), grid);
  } else {
    tz = sva_translation_bin(t.z, grid);
    SVA_PRECISE vec3 r = sva_quat_to_rodrigues(q);
    rx = sva_rotation_bin(r.x, grid);
    ry = sva_rotation_bin(r.y, grid);
    rz = sva_rotation_bin(r.z, grid);
  }
  if (tx < 0 || ty < 0 || tz < 0) return vote;
  SVA_PRECISE float w8 = likelihood * (sva_beta_weight(al, i, n) / weight_sum);
  vote.key = sva_pack_bin_key(object, tx, ty, tz, rx, ry, rz);
  vote.mass = SVA_TO_FIXED(w8);
  vote.inside = 1;
  return vote;
}

#endif
