#pragma once
// The beta samples of one match, evaluated several at a time (the CPU reference's vote math at the machine's
// width). sva_vote_math.h is the one text of the vote, a function per sample as a GPU thread runs it; its functions
// are written as selects, not branches, so here the same functions run over the match's samples in
// structure-of-arrays loops that the compiler turns into SIMD lanes (8 in the x86-64-v3 clone, AVX2). Nothing is
// reassociated or fused (-ffp-contract=off), division and square root are the IEEE ones, so every sample's pose bin
// and fixed-point mass are sva_vote's bit for bit (tests/backends/cpu/test_sample_votes.cpp compares them on
// simulated data and on the hard cases).
#include <cstdint>

#include "votes/vote_math.hpp"

namespace sva::cpu {

// One match's votes, one slot per beta sample (structure of arrays, padded to whole groups of lanes).
struct SampleVotes {
  static constexpr int kLanes = 8;
  static constexpr int kCapacity = (SVA_MAX_BETA_SAMPLES + kLanes - 1) / kLanes * kLanes;
  int n = 0;                                   // samples of the match (the plan's n)
  alignas(32) std::uint64_t key[kCapacity];    // pose bin key (0 where not inside)
  alignas(32) std::int32_t mass[kCapacity];    // fixed-point mass, SVA_TO_FIXED (at most 2^24; 0 where not inside)
  alignas(32) std::int32_t inside[kCapacity];  // 1: the pose lies in the pose space (and is planar, in a planar one)
};

// Every beta sample of a match with likelihood `likelihood`: the Gaussian weights (sva_beta_weights), their sum in
// sample order, the mass scale (sva_vote_scale) and each sample's vote (sva_vote), bit for bit.
void sample_votes(const vote_math::SvaAlignment& al, const vote_math::SvaBetaPlan& plan,
                  const vote_math::SvaPoseGrid& grid, std::uint32_t object, float likelihood, SampleVotes* out);

}  // namespace sva::cpu
