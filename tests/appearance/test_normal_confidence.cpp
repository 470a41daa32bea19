#include <catch2/catch.hpp>

#include "appearance/normal_confidence.hpp"

using namespace sva;

TEST_CASE("normConf: symmetric eigenvalues of known matrices") {
  const auto diag = appearance::symmetric_eigenvalues({{{{2, 0, 0}}, {{0, 5, 0}}, {{0, 0, 1}}}});
  CHECK(diag[0] == Approx(5));
  CHECK(diag[1] == Approx(2));
  CHECK(diag[2] == Approx(1));
  // [[2,1,0],[1,2,0],[0,0,3]]: eigenvalues 3, 3, 1.
  const auto ev = appearance::symmetric_eigenvalues({{{{2, 1, 0}}, {{1, 2, 0}}, {{0, 0, 3}}}});
  CHECK(ev[0] == Approx(3));
  CHECK(ev[1] == Approx(3));
  CHECK(ev[2] == Approx(1));
  // Rank one: v v^T with v = (1, 2, 3).
  const auto r1 = appearance::symmetric_eigenvalues({{{{1, 2, 3}}, {{2, 4, 6}}, {{3, 6, 9}}}});
  CHECK(r1[0] == Approx(14));
  CHECK(r1[1] == Approx(0).margin(1e-9));
}

TEST_CASE("normConf: planar, line and point contacts") {
  const SensorSpec s;
  std::vector<float> flat(36, 20.0f);
  CHECK(appearance::normal_confidence(flat, s, 100.0, 2.0) == Approx(1.0f).margin(1e-5));
  std::vector<float> rect(36, 0.0f);  // 2 x 6 patch: spreads differ
  for (int r = 2; r < 4; ++r)
    for (int c = 0; c < 6; ++c) rect[static_cast<std::size_t>(r * 6 + c)] = 20.0f;
  const float rc = appearance::normal_confidence(rect, s, 100.0, 2.0);
  CHECK(rc > 0.1f);
  CHECK(rc < 0.5f);
  std::vector<float> line(36, 0.0f);  // one row at equal depth: colinear
  for (int c = 0; c < 6; ++c) line[static_cast<std::size_t>(2 * 6 + c)] = 20.0f;
  CHECK(appearance::normal_confidence(line, s, 100.0, 2.0) == 0.0f);
  std::vector<float> two(36, 0.0f);
  two[0] = two[7] = 30.0f;
  CHECK(appearance::normal_confidence(two, s, 100.0, 2.0) == 0.0f);
  CHECK(appearance::normal_confidence(std::vector<float>(36, 0.0f), s, 100.0, 2.0) == 0.0f);
  std::vector<float> nan(36, std::nanf(""));
  CHECK(appearance::normal_confidence(nan, s, 100.0, 2.0) == 0.0f);
}
