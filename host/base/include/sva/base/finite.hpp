#pragma once
// The one test of "a number, not NaN or infinite" for vectors and matrices, which every input check uses.
#include <cmath>
#include <glm/glm.hpp>

namespace sva {

inline bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline bool finite(const glm::dmat3& m) { return finite(m[0]) && finite(m[1]) && finite(m[2]); }

}  // namespace sva
