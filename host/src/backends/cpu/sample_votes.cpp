// The beta samples of one match, lane by lane (sample_votes.hpp says why and how). Every formula is the shared
// text's own function (written as selects there, so that these loops vectorise); only the loops' shape and the
// fixed-point conversion's width are this file's.
#include "backends/cpu/sample_votes.hpp"

#include <algorithm>
#include <cmath>

#include "backends/cpu/hot_path.hpp"

namespace sva::cpu {

namespace {

using namespace vote_math;  // the shared text's names (vec3, vec4, sva_*)

constexpr int kCap = SampleVotes::kCapacity;
constexpr int kLanes = SampleVotes::kLanes;

// The samples rounded up to whole groups of lanes: the loops run over these (the lanes past n are computed and
// never read), so that a match of 9 samples costs two groups, not kCap / kLanes.
inline int lanes_for(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

// sva_beta_weights' weights (without the sum, which is taken in sample order afterwards). Sample n-1-i sits at
// exactly minus sample i's offset (sva_beta_offset: a signed integer times the unit), so its weight has the same
// bits: the first half is computed and mirrored. The padding lanes past n are set to 0.
SVA_HOT_PATH void beta_weights(const SvaBetaPlan& plan, float* __restrict w) {
  const int half = (plan.n + 1) / 2;
  const int lanes = lanes_for(half);
  for (int i = 0; i < lanes; ++i) w[i] = sva_beta_weight(plan, i);
  for (int i = half; i < plan.n; ++i) w[i] = w[plan.n - 1 - i];
  for (int i = plan.n; i < lanes_for(plan.n); ++i) w[i] = 0.0f;
}

// sva_vote for every sample: its pose bins, fixed-point mass and whether it is inside. 32-bit lanes throughout (the
// keys' 64-bit packing is a loop of its own: mixing widths in one loop keeps the compiler from vectorising it).
struct SampleBins {
  alignas(32) std::int32_t tx[kCap], ty[kCap], tz[kCap], rx[kCap], ry[kCap], rz[kCap];
  alignas(32) float qx[kCap], qy[kCap], qz[kCap], qw[kCap];  // each sample's rotation about the axis, between loops
};

// One pair of loops per kind of pose space (a template, so that neither tests the kind per sample). The first turns
// each sample about the axis and bins its translation, the second composes its rotation and bins that: one loop
// holding both kept more values than the registers hold and spilled them every sample.
template <bool kPlanar>
inline void bins_and_masses_of(const SvaAlignment& al, const SvaBetaPlan& plan, const SvaPoseGrid& grid,
                               const float* __restrict weight, float scale, SampleBins* __restrict bins,
                               SampleVotes* __restrict out) {
  const int lanes = lanes_for(plan.n);
  for (int i = 0; i < lanes; ++i) {
    const float beta = al.beta_hat + sva_beta_offset(plan, i);
    const vec4 qb = sva_quat_axis_angle(al.axis, beta);
    const vec3 t = al.c_obs - sva_quat_rotate(qb, al.c_map_r);
    bins->tx[i] = sva_translation_bin(t.x, grid);
    bins->ty[i] = sva_translation_bin(t.y, grid);
    bins->tz[i] = kPlanar ? 0 : sva_translation_bin(t.z, grid);
    bins->qx[i] = qb.x;
    bins->qy[i] = qb.y;
    bins->qz[i] = qb.z;
    bins->qw[i] = qb.w;
  }
  for (int i = 0; i < lanes; ++i) {
    const vec4 q = sva_quat_mul(vec4(bins->qx[i], bins->qy[i], bins->qz[i], bins->qw[i]), al.q1);
    int in = (bins->tx[i] | bins->ty[i] | bins->tz[i]) >= 0 ? 1 : 0;  // each bin is -1 outside
    if constexpr (kPlanar) {
      in = sva_planar_tilted(q) ? 0 : in;
      bins->rx[i] = 0;
      bins->ry[i] = 0;
      bins->rz[i] = sva_planar_rotation_bin(q, grid);
    } else {
      const vec3 r = sva_quat_to_rodrigues(q);
      bins->rx[i] = sva_rotation_bin(r.x, grid);
      bins->ry[i] = sva_rotation_bin(r.y, grid);
      bins->rz[i] = sva_rotation_bin(r.z, grid);
    }
    // SVA_TO_FIXED, converted to 32 bits (exact: at most 2^24 units), which the lanes have.
    const float m = weight[i] * scale;
    out->mass[i] = static_cast<std::int32_t>(SVA_FIXED_UNITS(m)) * in;
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
