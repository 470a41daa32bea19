// One source of truth for constants and layouts used by both the C++ host and
// the GLSL compute shaders. Included verbatim by both languages, so it holds
// only #defines and plain arithmetic that both accept.
#ifndef SVA_SHARED_H
#define SVA_SHARED_H

// Vote mass is accumulated as 64-bit fixed point: integer sums are
// order-independent, so CPU and GPU (any thread count) agree bit for bit.
// One unit of vote weight (a full-probability vote) is 2^SVA_FIXED_SHIFT.
#define SVA_FIXED_SHIFT 24
#define SVA_FIXED_ONE (1u << SVA_FIXED_SHIFT)
// Quantise a vote weight: NaN and negatives give 0, weights above 1 clamp to 1,
// and the rest round to the nearest unit (half up): truncation would bias every
// vote low. The multiply by a power of two is exact in float; below 2^23 adding
// 0.5 is exact too, and above it every float is already a whole number, so host
// and shader produce the same integer for the same float. In C++ it needs `min`
// and `floor` in scope (sva::to_fixed provides them).
#define SVA_ROUND_UNITS(v) ((v) < 8388608.0f ? floor((v) + 0.5f) : (v))
// The whole units as a float (at most 2^24, exact in a 32-bit integer too: the CPU's lanes convert it so).
#define SVA_FIXED_UNITS(w) SVA_ROUND_UNITS(((w) > 0.0f ? min((w), 1.0f) : 0.0f) * float(SVA_FIXED_ONE))
#define SVA_TO_FIXED(w) int64_t(SVA_FIXED_UNITS(w))
// A single vote is clamped to this many units so that even 2^32 votes into one
// bin cannot overflow a signed 64-bit sum: 2^24 * 2^32 = 2^56 < 2^63.
#define SVA_FIXED_MAX_VOTE_UNITS SVA_FIXED_ONE

// Compute workgroup width for 1-D kernels. 64 is a multiple of every subgroup
// width we meet (8 on lavapipe, 32 on NVIDIA); nothing assumes the width.
#define SVA_WORKGROUP_SIZE 64

// Empty slot marker of the open-addressing GPU hash table (64-bit keys).
#define SVA_HASH_EMPTY_KEY_LO 0xffffffffu
#define SVA_HASH_EMPTY_KEY_HI 0xffffffffu
// Longest probe sequence before a key insert reports overflow to the host.
#define SVA_HASH_MAX_PROBE 64

#endif
