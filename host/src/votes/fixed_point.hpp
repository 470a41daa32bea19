#pragma once
// Host side of the fixed-point vote rule shared with the shaders.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sva {
using std::floor;
using std::min;
#include "sva_shared.h"

inline std::int64_t to_fixed(float w) { return SVA_TO_FIXED(w); }
inline double from_fixed(std::int64_t v) { return static_cast<double>(v) / static_cast<double>(SVA_FIXED_ONE); }

}  // namespace sva
