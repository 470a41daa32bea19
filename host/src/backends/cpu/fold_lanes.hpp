#pragma once
// A pair's fold terms several bins at a time (the CPU reference's fold at the machine's width).
// sva_belief_math.h's log2 squares a 32-bit mantissa 32 times, each squaring waiting for the last: one bin's term is
// a chain of 32 dependent multiplications. Here the chains of 32 bins run side by side, in SIMD lanes where the
// machine has them (GCC 12 vectorizes them for x86-64-v3 and v4: 2.4x the scalar chains on AVX-512, 1.3x on AVX2),
// with the same integer operations, so every term is sva_fold_units_given's bit for bit
// (tests/backends/cpu/test_fold_lanes.cpp); the last bins of a pair, fewer than a group, take the shared text.
#include <cstddef>
#include <cstdint>

namespace sva::cpu {

// out[i] = sva_fold_units_given(mass[i], total, eps_units, floor_log) for i < n (each 0 < mass[i] <= total).
void fold_units(const std::uint64_t* mass, std::size_t n, std::uint64_t total, std::uint64_t eps_units,
                std::uint64_t floor_log, std::uint64_t* out);

}  // namespace sva::cpu
