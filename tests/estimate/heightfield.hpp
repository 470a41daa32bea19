#pragma once
// Twins as meshes for the measurement model's and the planner's tests: a 40 x 40 mm heightfield on a 5 mm grid (9 x
// 9 vertices, z up, counter-clockwise from above), flat, or with the vertices (3..5, 3..5) raised by 6 mm: a 10 x
// 10 mm plateau with slopes around it over [10, 30]^2, the one region where the two differ.
#include <sva/map.hpp>

#include <cstdint>

namespace sva::test {

inline ObjectSurface heightfield(bool raised) {
  ObjectSurface s;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) {
      const bool up = raised && i >= 3 && i <= 5 && j >= 3 && j <= 5;
      s.positions.emplace_back(5.0f * static_cast<float>(i), 5.0f * static_cast<float>(j), up ? 6.0f : 0.0f);
    }
  auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * 9 + i); };
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      s.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      s.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return s;
}

}  // namespace sva::test
