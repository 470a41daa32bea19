// A block of matches aligned and planned lane by lane (align_lanes.hpp says why and how). The formulas are
// sva_align's and sva_beta_plan's own text; only the loop's shape (patches gathered into arrays, one lane per match)
// is this file's.
#include "backends/cpu/align_lanes.hpp"

#include "backends/cpu/hot_path.hpp"

namespace sva::cpu {

namespace {

using namespace vote_math;  // the shared text's names (vec3, vec4, sva_*)

constexpr int kLanes = MatchLanes::kLanes;
static_assert(PatchLanes::kLanes == kLanes);

// The block's map pairs' ends gathered into lanes.
void gather(std::span<const SvaPatch> patches, const std::uint32_t* reading, int n, PatchLanes* out) {
  for (int l = 0; l < kLanes; ++l) out->set(l, patches[reading[l < n ? l : 0]]);  // past n: the first, never read
}

// The block's alignments and plans, a field per array (a loop the compiler can vectorise writes arrays, not
// structures).
struct AlignmentLanes {
  alignas(32) float qx[kLanes], qy[kLanes], qz[kLanes], qw[kLanes];
  alignas(32) float ux[kLanes], uy[kLanes], uz[kLanes];
  alignas(32) float cx[kLanes], cy[kLanes], cz[kLanes];
  alignas(32) float mx[kLanes], my[kLanes], mz[kLanes];
  alignas(32) float beta[kLanes], conf[kLanes], sigma[kLanes];
  alignas(32) std::int32_t valid[kLanes];
  alignas(32) std::int32_t n[kLanes], circle[kLanes];
  alignas(32) float unit[kLanes], inv_sigma[kLanes];
};

SVA_HOT_PATH void align_all(const PatchLanes& a1, const PatchLanes& b1, const PatchLanes& a2, const PatchLanes& b2,
                            const SvaPoseGrid& grid, AlignmentLanes* __restrict out) {
  for (int l = 0; l < kLanes; ++l) {
    const SvaAlignment al = sva_align(a1.at(l), b1.at(l), a2.at(l), b2.at(l));
    const SvaBetaPlan plan = sva_beta_plan(al, grid);
    out->n[l] = plan.n;
    out->circle[l] = plan.circle;
    out->unit[l] = plan.unit;
    out->inv_sigma[l] = plan.inv_sigma;
    out->qx[l] = al.q1.x;
    out->qy[l] = al.q1.y;
    out->qz[l] = al.q1.z;
    out->qw[l] = al.q1.w;
    out->ux[l] = al.axis.x;
    out->uy[l] = al.axis.y;
    out->uz[l] = al.axis.z;
    out->cx[l] = al.c_obs.x;
    out->cy[l] = al.c_obs.y;
    out->cz[l] = al.c_obs.z;
    out->mx[l] = al.c_map_r.x;
    out->my[l] = al.c_map_r.y;
    out->mz[l] = al.c_map_r.z;
    out->beta[l] = al.beta_hat;
    out->conf[l] = al.align_conf;
    out->sigma[l] = al.sigma;
    out->valid[l] = al.valid;
  }
}

}  // namespace

ObservedLanes::ObservedLanes(const SvaPatch& a1, const SvaPatch& b1) {
  for (int l = 0; l < kLanes; ++l) {
    a.set(l, a1);
    b.set(l, b1);
  }
}

void align_lanes(const ObservedLanes& observed, std::span<const SvaPatch> patches, const SvaPoseGrid& grid,
                 const MatchLanes& block, SvaAlignment* out, SvaBetaPlan* plan) {
  if (block.n <= 0) return;
  PatchLanes a2, b2;
  gather(patches, block.ra, block.n, &a2);
  gather(patches, block.rb, block.n, &b2);
  AlignmentLanes lanes;
  align_all(observed.a, observed.b, a2, b2, grid, &lanes);
  for (int l = 0; l < block.n; ++l) {
    SvaAlignment& al = out[l];
    al.q1 = vec4(lanes.qx[l], lanes.qy[l], lanes.qz[l], lanes.qw[l]);
    al.axis = vec3(lanes.ux[l], lanes.uy[l], lanes.uz[l]);
    al.c_obs = vec3(lanes.cx[l], lanes.cy[l], lanes.cz[l]);
    al.c_map_r = vec3(lanes.mx[l], lanes.my[l], lanes.mz[l]);
    al.beta_hat = lanes.beta[l];
    al.align_conf = lanes.conf[l];
    al.sigma = lanes.sigma[l];
    al.valid = lanes.valid[l];
    plan[l].n = lanes.n[l];
    plan[l].circle = lanes.circle[l];
    plan[l].unit = lanes.unit[l];
    plan[l].inv_sigma = lanes.inv_sigma[l];
  }
}

}  // namespace sva::cpu
