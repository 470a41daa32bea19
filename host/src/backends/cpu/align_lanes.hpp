#pragma once
// The alignments and beta plans of several matches of one observed pair, side by side (the CPU reference's
// alignment at the machine's width). sva_align (shaders/include/sva_alignment.h) and sva_beta_plan
// (sva_beta_sampling.h) are one match's alignment and plan as a GPU thread runs them, written as selects; here they
// run over a block of matches in a structure-of-arrays loop that the compiler turns into SIMD lanes (8 in the
// x86-64-v3 clone), so each is sva_align's and sva_beta_plan's bit for bit (tests/backends/cpu/test_align_lanes.cpp
// compares them on simulated pairs and on the hard cases).
#include <cstdint>
#include <span>

#include "votes/vote_math.hpp"

namespace sva::cpu {

// One end of a block's pairs, a coordinate per array.
struct PatchLanes {
  static constexpr int kLanes = 8;
  alignas(32) float px[kLanes], py[kLanes], pz[kLanes], nx[kLanes], ny[kLanes], nz[kLanes], conf[kLanes];
  void set(int l, const vote_math::SvaPatch& p) {
    px[l] = p.p.x;
    py[l] = p.p.y;
    pz[l] = p.p.z;
    nx[l] = p.n.x;
    ny[l] = p.n.y;
    nz[l] = p.n.z;
    conf[l] = p.conf;
  }
  vote_math::SvaPatch at(int l) const {
    vote_math::SvaPatch p;
    p.p = vote_math::vec3(px[l], py[l], pz[l]);
    p.n = vote_math::vec3(nx[l], ny[l], nz[l]);
    p.conf = conf[l];
    return p;
  }
};

// The observed pair in every lane, made once per pair: a value the compiler holds in a scalar register would leave
// the selects on it (the clamp of its normal confidence) as a scalar condition among vectors, which it cannot
// vectorise.
struct ObservedLanes {
  PatchLanes a, b;
  ObservedLanes(const vote_math::SvaPatch& a1, const vote_math::SvaPatch& b1);
};

// A block of matches of one observed pair: the two map readings of each, the object and the likelihood.
struct MatchLanes {
  static constexpr int kLanes = 8;
  int n = 0;  // matches held, at most kLanes
  std::uint32_t ra[kLanes] = {}, rb[kLanes] = {}, object[kLanes] = {};
  float likelihood[kLanes] = {};
};

// For each of the block's n matches i: al[i] = sva_align(a1, b1, patches[ra[i]], patches[rb[i]]) and
// plan[i] = sva_beta_plan(al[i], grid), with the observed pair (a1, b1) in `observed`.
void align_lanes(const ObservedLanes& observed, std::span<const vote_math::SvaPatch> patches,
                 const vote_math::SvaPoseGrid& grid, const MatchLanes& block, vote_math::SvaAlignment* al,
                 vote_math::SvaBetaPlan* plan);

}  // namespace sva::cpu
