// The beta samples of one match, lane by lane (sample_votes.hpp says why and how). Each function below is the
// shared text's function of the same name (sva_fast_math.h, sva_quaternion.h, sva_pose_bins.h, sva_vote_math.h)
// with its branches turned into selects: the same operations in the same order, so the same bits. The
// polynomials and the quaternion products are the shared text itself.
#include "backends/cpu/sample_votes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "util/hot_path.hpp"

namespace sva::cpu {

namespace {

using namespace vote_math;  // the shared text's names (vec3, vec4, sva_*)

constexpr int kCap = SampleVotes::kCapacity;
constexpr int kLanes = SampleVotes::kLanes;

// The samples rounded up to whole groups of lanes: the loops run over these (the lanes past n are computed and
// never read), so that a match of 9 samples costs two groups, not kCap / kLanes.
inline int lanes_for(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

// sva_exp_neg: 0 below -80, x > 0 taken as 0; the series times the exact 2^-k.
inline float exp_neg(float x) {
  const bool below = !(x > -80.0f);
  float xc = x > 0.0f ? 0.0f : x;
  xc = below ? 0.0f : xc;
  const float kf = std::floor(xc * SVA_INV_LN2 + 0.5f);
  const float r = xc - kf * SVA_LN2;
  const float e = sva_exp_series(r);
  const int k = static_cast<int>(-kf);
  const float scale = std::bit_cast<float>(static_cast<std::uint32_t>(127 - k) << 23);
  const float v = e * scale;
  return below ? 0.0f : v;
}

// sva_atan2 (with sva_atan01 inside); atan2(0, 0) = 0.
inline float atan2_lane(float y, float x) {
  const float ax = std::fabs(x);
  const float ay = std::fabs(y);
  const float hi = std::max(ax, ay);
  const bool none = !(hi > 0.0f);
  const float lo = std::min(ax, ay);
  const float t = sva_div(lo, none ? 1.0f : hi);
  const bool reduce = t > 0.41421356f;
  const float base = reduce ? SVA_QUARTER_PI : 0.0f;
  const float u = reduce ? sva_div(t - 1.0f, t + 1.0f) : t;
  float a = base + sva_atan_series(u);
  a = ay > ax ? SVA_HALF_PI - a : a;
  a = x < 0.0f ? SVA_PI - a : a;
  a = y < 0.0f ? -a : a;
  return none ? 0.0f : a;
}

// sva_translation_bin: -1 outside the grid (NaN too).
inline int translation_bin(float t, const SvaPoseGrid& grid) {
  const float f = (t - grid.translation_min) * grid.translation_scale;
  const bool in = f >= 0.0f && f < static_cast<float>(grid.translation_bins);
  const int b = std::min(static_cast<int>(std::floor(in ? f : 0.0f)), grid.translation_bins - 1);
  return in ? b : -1;
}

// sva_rotation_bin.
inline int rotation_bin(float r, const SvaPoseGrid& grid) {
  const float f = (r + SVA_PI) * grid.rotation_scale;
  const bool in = f >= 0.0f;
  const int b = std::min(static_cast<int>(std::floor(in ? f : 0.0f)), grid.rotation_bins - 1);
  return in ? b : 0;
}

// sva_lead_positive.
inline vec3 lead_positive(vec3 v) {
  const float ax = std::fabs(v.x), ay = std::fabs(v.y), az = std::fabs(v.z);
  float lead = v.x;
  lead = ay > ax && ay >= az ? v.y : lead;
  lead = az > ax && az > ay ? v.z : lead;
  return lead < 0.0f ? -v : v;
}

// sva_quat_to_rodrigues.
inline vec3 rodrigues(vec4 q) {
  const bool flip = q.w < 0.0f;
  vec3 v = flip ? -vec3(q.x, q.y, q.z) : vec3(q.x, q.y, q.z);
  const float w = flip ? -q.w : q.w;
  v = w < SVA_NEAR_PI_W ? lead_positive(v) : v;
  const float s = sva_length(v);
  const bool zero = !(s > 0.0f);
  const float angle = 2.0f * atan2_lane(s, w);
  const float k = sva_div(angle, zero ? 1.0f : s);
  const vec3 r = v * k;
  return zero ? vec3(0.0f) : r;
}

// sva_beta_weights' weights (without the sum, which is taken in sample order afterwards).
SVA_HOT_PATH void beta_weights(const SvaBetaPlan& plan, float* __restrict w) {
  const int centre = (plan.n - 1) / 2;
  const int lanes = lanes_for(plan.n);
  for (int i = 0; i < lanes; ++i) {
    const int k = plan.circle != 0 ? 2 * i + 1 - plan.n : i - centre;
    const float z = plan.unit * static_cast<float>(k) * plan.inv_sigma;
    w[i] = exp_neg(-0.5f * z * z);
  }
}

// sva_vote for every sample: its pose bins, fixed-point mass and whether it is inside. 32-bit lanes throughout (the
// keys' 64-bit packing is a loop of its own: mixing widths in one loop keeps the compiler from vectorising it).
struct SampleBins {
  alignas(32) std::int32_t tx[kCap], ty[kCap], tz[kCap], rx[kCap], ry[kCap], rz[kCap];
};

// One loop per kind of pose space (a template, so that neither loop tests the kind per sample).
template <bool kPlanar>
inline void bins_and_masses_of(const SvaAlignment& al, const SvaBetaPlan& plan, const SvaPoseGrid& grid,
                               const float* __restrict weight, float scale, SampleBins* __restrict bins,
                               SampleVotes* __restrict out) {
  const int centre = (plan.n - 1) / 2;
  const int lanes = lanes_for(plan.n);
  for (int i = 0; i < lanes; ++i) {
    const int k = plan.circle != 0 ? 2 * i + 1 - plan.n : i - centre;
    const float beta = al.beta_hat + plan.unit * static_cast<float>(k);
    const vec4 qb = sva_quat_axis_angle(al.axis, beta);
    const vec3 t = al.c_obs - sva_quat_rotate(qb, al.c_map_r);
    const int tx = translation_bin(t.x, grid);
    const int ty = translation_bin(t.y, grid);
    const int tz = kPlanar ? 0 : translation_bin(t.z, grid);
    const vec4 q = sva_quat_mul(qb, al.q1);
    int in = (tx | ty | tz) >= 0 ? 1 : 0;  // each bin is -1 outside
    if constexpr (kPlanar) {
      // The angle about z; a sample that tilts z too far is not a planar pose.
      const float w = std::fabs(q.w);
      const float sz = q.w < 0.0f ? -q.z : q.z;
      in = q.x * q.x + q.y * q.y > SVA_PLANAR_MAX_TILT_SIN2 ? 0 : in;
      bins->rx[i] = 0;
      bins->ry[i] = 0;
      bins->rz[i] = rotation_bin(2.0f * atan2_lane(sz, w), grid);
    } else {
      const vec3 r = rodrigues(q);
      bins->rx[i] = rotation_bin(r.x, grid);
      bins->ry[i] = rotation_bin(r.y, grid);
      bins->rz[i] = rotation_bin(r.z, grid);
    }
    bins->tx[i] = tx;
    bins->ty[i] = ty;
    bins->tz[i] = tz;
    // SVA_TO_FIXED: at most 2^24 units, so the 32-bit conversion is the 64-bit one.
    const float m = weight[i] * scale;
    const float v = (m > 0.0f ? std::min(m, 1.0f) : 0.0f) * static_cast<float>(SVA_FIXED_ONE);
    const float units = v < 8388608.0f ? std::floor(v + 0.5f) : v;
    out->mass[i] = static_cast<std::int32_t>(units) * in;
    out->inside[i] = in;
  }
}

SVA_HOT_PATH void bins_and_masses(const SvaAlignment& al, const SvaBetaPlan& plan, const SvaPoseGrid& grid,
                                  const float* __restrict weight, float scale, SampleBins* __restrict bins,
                                  SampleVotes* __restrict out) {
  if (grid.kind == SVA_POSE_PLANAR)
    bins_and_masses_of<true>(al, plan, grid, weight, scale, bins, out);
  else
    bins_and_masses_of<false>(al, plan, grid, weight, scale, bins, out);
}

// sva_pack_bin_key, 0 where the sample is not inside.
SVA_HOT_PATH void pack_keys(std::uint32_t object, const SampleBins& bins, SampleVotes* out) {
  const std::uint64_t object_bits = static_cast<std::uint64_t>(object) << SVA_KEY_OBJECT_SHIFT;
  const auto field = [](std::int32_t bin, int shift) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(bin)) << shift;
  };
  const int lanes = lanes_for(out->n);
  for (int i = 0; i < lanes; ++i) {
    const std::uint64_t key = object_bits | field(bins.tx[i], SVA_KEY_TX_SHIFT) | field(bins.ty[i], SVA_KEY_TY_SHIFT) |
                              field(bins.tz[i], SVA_KEY_TZ_SHIFT) | field(bins.rx[i], SVA_KEY_RX_SHIFT) |
                              field(bins.ry[i], SVA_KEY_RY_SHIFT) | field(bins.rz[i], SVA_KEY_RZ_SHIFT);
    out->key[i] = key & (std::uint64_t{0} - static_cast<std::uint64_t>(out->inside[i]));
  }
}

}  // namespace

void sample_votes(const SvaAlignment& al, const SvaBetaPlan& plan, const SvaPoseGrid& grid, std::uint32_t object,
                  float likelihood, SampleVotes* out) {
  out->n = plan.n;
  if (plan.n <= 0) return;
  alignas(32) float weight[kCap];
  beta_weights(plan, weight);
  float sum = 0.0f;  // sva_beta_weights: in sample order
  for (int i = 0; i < plan.n; ++i) sum = sum + weight[i];
  SampleBins bins;
  bins_and_masses(al, plan, grid, weight, sva_vote_scale(likelihood, sum), &bins, out);
  pack_keys(object, bins, out);
}

}  // namespace sva::cpu
