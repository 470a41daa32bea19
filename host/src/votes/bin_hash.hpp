#pragma once
// The 64-bit key hash shared with the GPU hash tables (shaders/include/sva_hash.h).
#include <cstdint>

namespace sva::hash {
using std::uint64_t;
#include "sva_hash.h"
constexpr std::uint64_t kEmptyKey = SVA_HASH_EMPTY_KEY;
}  // namespace sva::hash
