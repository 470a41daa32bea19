// A block of matches aligned and planned lane by lane (align_lanes.hpp says why and how). The formulas are
// sva_align's and sva_beta_plan's own text; only the loop's shape (patches gathered into arrays, one lane per match)
// is this file's.
#include "backends/cpu/align_lanes.hpp"

#include "util/hot_path.hpp"

namespace sva::cpu {

namespace {

using namespace vote_math;  // the shared text's names (vec3, vec4, sva_*)

constexpr int kLanes = MatchLanes::kLanes;

// One end of the block's pairs, a coordinate per array.
struct PatchLanes {
  alignas(32) float px[kLanes], py[kLanes], pz[kLanes], nx[kLanes], ny[kLanes], nz[kLanes], conf[kLanes];
  void set(int l, const SvaPatch& p) {
    px[l] = p.p.x;
    py[l] = p.p.y;
    pz[l] = p.p.z;
    nx[l] = p.n.x;
    ny[l] = p.n.y;
    nz[l] = p.n.z;
    conf[l] = p.conf;
  }
  void gather(std::span<const SvaPatch> patches, const std::uint32_t* reading, int n) {
    for (int l = 0; l < kLanes; ++l) set(l, patches[reading[l < n ? l : 0]]);  // past n: the first again, never read
  }
  // The observed patch in every lane: a value the compiler holds in a scalar register would leave the selects on it
  // (the clamp of its normal confidence) as a scalar condition among vectors, which it cannot vectorise.
  void broadcast(const SvaPatch& p) {
    for (int l = 0; l < kLanes; ++l) set(l, p);
  }
  SvaPatch at(int l) const {
    SvaPatch p;
    p.p = vec3(px[l], py[l], pz[l]);
    p.n = vec3(nx[l], ny[l], nz[l]);
    p.conf = conf[l];
    return p;
  }
};

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

void align_lanes(const SvaPatch& a1, const SvaPatch& b1, std::span<const SvaPatch> patches, const SvaPoseGrid& grid,
                 const MatchLanes& block, SvaAlignment* out, SvaBetaPlan* plan) {
  if (block.n <= 0) return;
  PatchLanes a1s, b1s, a2, b2;
  a1s.broadcast(a1);
  b1s.broadcast(b1);
  a2.gather(patches, block.ra, block.n);
  b2.gather(patches, block.rb, block.n);
  AlignmentLanes lanes;
  align_all(a1s, b1s, a2, b2, grid, &lanes);
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
