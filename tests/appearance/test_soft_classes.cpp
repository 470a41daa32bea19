#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <cmath>

#include "appearance/appearance_model.hpp"
#include "appearance/soft_classes.hpp"

using namespace sva;

TEST_CASE("soft classes: psi (Eq 7) with the single-member floor") {
  // Medoids e_x, e_y, e_z; members of 0: e_x and (0.8, 0.6, 0) -> deviations 0, 0.2;
  // of 1: e_y and (0, 0.6, 0.8) -> 0, 0.4; class 2 has one member.
  const std::vector<float> medoids{1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<float> desc{1, 0, 0, 0.8f, 0.6f, 0, 0, 1, 0, 0, 0.6f, 0.8f, 0, 0, 1};
  const auto psi = appearance::cluster_psi(desc, medoids, {0, 0, 1, 1, 2}, 3);
  REQUIRE(psi.size() == 3);
  CHECK(psi[0] == Approx(0.04 / 2));
  CHECK(psi[1] == Approx(0.16 / 2));
  CHECK(psi[2] == Approx(0.08));  // floor: median of the positive ones {0.02, 0.08}
  // No positive psi anywhere: the default floor.
  const auto flat = appearance::cluster_psi({1, 0, 0}, {1, 0, 0}, {0}, 3);
  CHECK(flat[0] == Approx(appearance::kDefaultPsiFloor));
}

TEST_CASE("soft classes: Eq 8-12 against a hand-computed example") {
  AppearanceModel m;
  m.descriptor_size = 3;
  m.medoids = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.psi = {0.01f, 0.08f, 0.0025f};
  // v = (0.8, 0.6, 0): deviations 0.2, 0.4, 1.0.
  // Pr(v|c0) = exp(-0.04/0.02) / sqrt(2 pi 0.01)   = 0.539910
  // Pr(v|c1) = exp(-0.16/0.16) / sqrt(2 pi 0.08)   = 0.518884  (ratio 0.961 > T_a: kept)
  // Pr(v|c2) = exp(-1/0.005)   / sqrt(2 pi 0.0025) = 1.1e-86   (pruned)
  // Renormalised: 0.509929, 0.490071.
  const auto c = m.classify({0.8f, 0.6f, 0.0f});
  REQUIRE(c.size() == 2);
  CHECK(c[0].cls == 0);
  CHECK(c[0].weight == Approx(0.5099289).epsilon(1e-5));
  CHECK(c[1].cls == 1);
  CHECK(c[1].weight == Approx(0.4900711).epsilon(1e-5));
  // With psi_1 = 0.05 the ratio is 0.667 < 0.75: class 1 is pruned too.
  m.psi[1] = 0.05f;
  const auto one = m.classify({0.8f, 0.6f, 0.0f});
  REQUIRE(one.size() == 1);
  CHECK(one[0].cls == 0);
  CHECK(one[0].weight == 1.0f);
  // Far from every medoid with tiny psi: every Eq 8 value underflows, the
  // log-domain result still names the nearest class.
  m.psi = {1e-6f, 1e-6f, 1e-6f};
  const auto far = m.classify({0.0f, 0.6f, 0.8f});
  REQUIRE(far.size() == 1);
  CHECK(far[0].cls == 2);
  CHECK_THROWS_AS(m.classify({1.0f, 0.0f}), Error);
  CHECK_THROWS_AS(m.classify({NAN, 0.0f, 0.0f}), Error);
}

TEST_CASE("soft classes: weights are positive and sum to 1") {
  AppearanceModel m;
  m.descriptor_size = 4;
  util::Rng rng(4);
  for (int i = 0; i < 10; ++i) {
    std::vector<float> v(4);
    double s = 0;
    for (auto& x : v) {
      x = static_cast<float>(rng.uniform(0.1, 1.0));
      s += x * x;
    }
    for (auto& x : v) x = static_cast<float>(x / std::sqrt(s));
    m.medoids.insert(m.medoids.end(), v.begin(), v.end());
    m.psi.push_back(static_cast<float>(rng.uniform(0.001, 0.05)));
  }
  for (int t = 0; t < 50; ++t) {
    std::vector<float> v(4);
    double s = 0;
    for (auto& x : v) {
      x = static_cast<float>(rng.uniform(0.0, 1.0));
      s += x * x;
    }
    for (auto& x : v) x = static_cast<float>(x / std::sqrt(s));
    const auto c = m.classify(v);
    REQUIRE_FALSE(c.empty());
    double sum = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      CHECK(c[i].weight > 0.0f);
      if (i) CHECK(c[i].cls > c[i - 1].cls);
      sum += c[i].weight;
    }
    CHECK(sum == Approx(1.0).margin(1e-6));
  }
}

TEST_CASE("distance bins: Eq 13 with linear interpolation") {
  DistanceBins d;  // 40 bins over 30-160 mm: width 3.25, centre i at 31.625 + 3.25 i
  auto one = [](const std::vector<BinWeight>& b, std::uint32_t bin) {
    return b.size() == 1 && b[0].bin == bin && b[0].weight == 1.0f;
  };
  CHECK(one(d.bins(30.0), 0));
  CHECK(one(d.bins(31.0), 0));    // between min and the first centre
  CHECK(one(d.bins(31.625), 0));  // on a centre
  CHECK(one(d.bins(159.0), 39));  // between the last centre and max
  CHECK(one(d.bins(160.0), 39));
  CHECK(d.bins(29.999).empty());
  CHECK(d.bins(160.001).empty());
  CHECK(d.bins(NAN).empty());
  CHECK(d.bins(-INFINITY).empty());
  const auto b = d.bins(33.0);  // t = 3/3.25 - 0.5 = 0.423077
  REQUIRE(b.size() == 2);
  CHECK(b[0].bin == 0);
  CHECK(b[1].bin == 1);
  CHECK(b[0].weight == Approx(0.576923f).epsilon(1e-5));
  CHECK(b[1].weight == Approx(0.423077f).epsilon(1e-5));
  const auto mid = d.bins(31.625 + 3.25 * 10.5);  // half-way between centres 10 and 11
  REQUIRE(mid.size() == 2);
  CHECK(mid[0].bin == 10);
  CHECK(mid[0].weight == Approx(0.5f));
  util::Rng rng(2);
  for (int i = 0; i < 200; ++i) {
    const auto w = d.bins(rng.uniform(30.0, 160.0));
    REQUIRE_FALSE(w.empty());
    double s = 0;
    for (const auto& x : w) s += x.weight;
    CHECK(s == Approx(1.0).margin(1e-6));
  }
}
