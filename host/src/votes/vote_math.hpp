#pragma once
// The shared per-match vote math (shaders/include/sva_vote_math.h) compiled as
// C++. The header is written in the common subset of GLSL and glm, so it is
// included inside a namespace where glm's vector types and functions stand in
// for GLSL's. Every .cpp that includes this must be compiled with
// -ffp-contract=off (sva_core is, see host/CMakeLists.txt) so that float
// expressions round exactly as written, as they do on the GPU.
#include <cstdint>

#include <glm/glm.hpp>

#include "votes/fixed_point.hpp"

namespace sva::vote_math {
using namespace glm;
using std::int64_t;
using std::uint64_t;
#include "sva_vote_math.h"
}  // namespace sva::vote_math
