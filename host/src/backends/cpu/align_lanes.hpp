#pragma once
// The alignments of several matches of one observed pair, side by side (the CPU reference's alignment at the
// machine's width). sva_align (shaders/include/sva_alignment.h) is one match's alignment as a GPU thread runs it,
// written as selects; here it runs over a block of matches in a structure-of-arrays loop that the compiler turns
// into SIMD lanes (8 in the x86-64-v3 clone), so each alignment is sva_align's bit for bit
// (tests/backends/cpu/test_align_lanes.cpp compares them on simulated pairs and on the hard cases).
#include <cstdint>
#include <span>

#include "votes/vote_math.hpp"

namespace sva::cpu {

// A block of matches of one observed pair: the two map readings of each, the object and the likelihood.
struct MatchLanes {
  static constexpr int kLanes = 8;
  int n = 0;  // matches held, at most kLanes
  std::uint32_t ra[kLanes] = {}, rb[kLanes] = {}, object[kLanes] = {};
  float likelihood[kLanes] = {};
};

// sva_align(a1, b1, patches[ra[i]], patches[rb[i]]) for each of the block's n matches, into out[0, n).
void align_lanes(const vote_math::SvaPatch& a1, const vote_math::SvaPatch& b1,
                 std::span<const vote_math::SvaPatch> patches, const MatchLanes& block, vote_math::SvaAlignment* out);

}  // namespace sva::cpu
