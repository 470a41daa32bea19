// Trial generation: uniform SO(3) sampling, pose ranges, reading order and
// transformation, determinism across seeds and thread counts.
#include <catch2/catch.hpp>

#include <sva/base/parallel.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>
#include <sva/eval/trials.hpp>

#include <cmath>
#include <numbers>
#include <set>

#include <sva/base/so3.hpp>
#include "eval/metrics.hpp"
#include "training/session_sampling.hpp"

using namespace sva;
using namespace sva::eval;

namespace {

// A synthetic test set: `per_object` converged readings per object on a ring
// around the origin, plus one unconverged reading per object that must never
// be presented.
Dataset make_test_set(std::size_t objects, std::size_t per_object, bool planar = false) {
  Dataset d;
  d.scene.name = "unit";
  for (std::size_t o = 0; o < objects; ++o) {
    SceneObject so;
    so.name = "obj" + std::to_string(o);
    so.mesh = "/nonexistent/obj.glb";
    d.scene.objects.push_back(so);
  }
  if (planar) d.scene.pose_space = {PoseSpaceSpec::Kind::planar, 21, -10.0, 10.0, 9};
  for (std::size_t o = 0; o < objects; ++o) {
    for (std::size_t k = 0; k <= per_object; ++k) {
      Sample s;
      s.object = static_cast<std::uint32_t>(o);
      double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(per_object + 1);
      s.reading.position = {40.0 * std::cos(a), 40.0 * std::sin(a), 5.0 * static_cast<double>(o)};
      s.reading.normal = {std::cos(a), std::sin(a), 0.0};
      s.reading.x_axis = {0.0, 0.0, 1.0};
      s.reading.pressure.assign(36, static_cast<float>(k));
      if (k == per_object) s.reading.status = ControllerStatus::not_converged;
      d.samples.push_back(s);
    }
  }
  return d;
}

bool same(const Trial& a, const Trial& b) {
  if (a.object != b.object || a.samples != b.samples || a.pose.T != b.pose.T || a.pose.R != b.pose.R) return false;
  for (std::size_t i = 0; i < a.readings.size(); ++i)
    if (a.readings[i].position != b.readings[i].position || a.readings[i].normal != b.readings[i].normal) return false;
  return true;
}

}  // namespace

TEST_CASE("uniform SO(3) sampling: rotations, zero mean matrix, Haar angle distribution") {
  util::Rng rng(11, 0);
  const int n = 20000;
  glm::dmat3 sum(0.0);
  int below_half_pi = 0;
  for (int i = 0; i < n; ++i) {
    glm::dmat3 R = uniform_rotation(rng);
    REQUIRE(glm::determinant(R) == Approx(1.0).margin(1e-9));
    glm::dmat3 E = glm::transpose(R) * R;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) REQUIRE(E[c][r] == Approx(c == r ? 1.0 : 0.0).margin(1e-9));
    sum += R;
    below_half_pi += so3::angle_sincos(R) < std::numbers::pi / 2;
  }
  // E[R] = 0 under the Haar measure; each entry has variance 1/3.
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) CHECK(std::abs(sum[c][r] / n) < 4.0 * std::sqrt(1.0 / 3.0 / n));
  // The angle density is (1 - cos t) / pi, so P(t < pi/2) = (pi/2 - 1) / pi ~= 0.1817.
  const double expected = (std::numbers::pi / 2 - 1.0) / std::numbers::pi;
  const double sd = std::sqrt(expected * (1 - expected) / n);
  CHECK(std::abs(static_cast<double>(below_half_pi) / n - expected) < 4.0 * sd);
}

TEST_CASE("random poses stay in the pose space ranges") {
  util::Rng rng(5, 9);
  PoseSpaceSpec spatial;  // [-200, 200]
  PoseSpaceSpec planar{PoseSpaceSpec::Kind::planar, 21, -10.0, 10.0, 9};
  double max_abs = 0.0;
  for (int i = 0; i < 2000; ++i) {
    RigidPose p = random_pose(rng, spatial);
    for (int k = 0; k < 3; ++k) {
      REQUIRE(std::abs(p.T[k]) <= 200.0);
      max_abs = std::max(max_abs, std::abs(p.T[k]));
    }
    RigidPose q = random_pose(rng, planar);
    REQUIRE(std::abs(q.T.x) <= 10.0);
    REQUIRE(std::abs(q.T.y) <= 10.0);
    REQUIRE(q.T.z == 0.0);
    REQUIRE(q.R[2][2] == Approx(1.0));  // rotation about z only
  }
  CHECK(max_abs > 190.0);  // the range is used, not only its middle
}

TEST_CASE("trials cycle through objects, present distinct converged readings, transformed by the pose") {
  Dataset d = make_test_set(3, 8);
  TrialGenerator gen(d, d.scene.pose_space, 42, 6, "unit");
  for (std::size_t t = 0; t < 9; ++t) {
    Trial tr = gen.make(t);
    CHECK(tr.object == t % 3);
    REQUIRE(tr.readings.size() == 6);
    std::set<std::size_t> distinct(tr.samples.begin(), tr.samples.end());
    CHECK(distinct.size() == 6);
    for (std::size_t k = 0; k < 6; ++k) {
      const Reading& original = d.samples[tr.samples[k]].reading;
      CHECK(d.samples[tr.samples[k]].object == tr.object);
      CHECK(original.status == ControllerStatus::converged);
      CHECK(glm::length(tr.readings[k].position - tr.pose.apply(original.position)) < 1e-9);
      CHECK(glm::length(tr.readings[k].normal - tr.pose.R * original.normal) < 1e-12);
      CHECK(glm::length(tr.readings[k].x_axis - tr.pose.R * original.x_axis) < 1e-12);
      CHECK(tr.readings[k].pressure == original.pressure);
    }
  }
}

TEST_CASE("more readings than the test set: every reading once, then with replacement") {
  Dataset d = make_test_set(2, 5);
  TrialGenerator gen(d, d.scene.pose_space, 1, 12, "unit");
  Trial tr = gen.make(0);
  REQUIRE(tr.samples.size() == 12);
  std::set<std::size_t> first(tr.samples.begin(), tr.samples.begin() + 5);
  CHECK(first.size() == 5);
  for (std::size_t s : tr.samples) CHECK(d.samples[s].object == 0);
}

TEST_CASE("readings stored in a moved object's frame are brought back to the object frame") {
  Dataset d = make_test_set(1, 4);
  RigidPose session{glm::dmat3(glm::dvec3(0, 1, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 0, 1)), {3, -2, 1}};
  Dataset moved = d;
  for (auto& s : moved.samples) {
    s.object_pose = session;
    s.reading.position = session.apply(s.reading.position);
    s.reading.normal = session.rotate(s.reading.normal);
    s.reading.x_axis = session.rotate(s.reading.x_axis);
  }
  Trial a = TrialGenerator(d, d.scene.pose_space, 9, 4).make(0);
  Trial b = TrialGenerator(moved, moved.scene.pose_space, 9, 4).make(0);
  REQUIRE(a.samples == b.samples);
  for (std::size_t k = 0; k < 4; ++k) CHECK(glm::length(a.readings[k].position - b.readings[k].position) < 1e-9);
}

TEST_CASE("same seed gives the same trials on any thread count and another seed other trials") {
  Dataset d = make_test_set(4, 20);
  const std::size_t n = 24;
  auto build = [&](std::uint64_t seed, unsigned threads) {
    TrialGenerator gen(d, d.scene.pose_space, seed, 10);
    std::vector<Trial> out(n);
    util::parallel_for(
        n, [&](std::size_t t) { out[t] = gen.make(t); }, threads);
    return out;
  };
  auto one = build(17, 1), two = build(17, 2), again = build(17, 2), other = build(18, 1);
  std::size_t differ = 0;
  for (std::size_t t = 0; t < n; ++t) {
    CHECK(same(one[t], two[t]));
    CHECK(same(one[t], again[t]));
    differ += !same(one[t], other[t]);
  }
  CHECK(differ == n);
}

TEST_CASE("bad test sets are refused with a message naming the fault") {
  PoseSpaceSpec space;
  SECTION("no converged readings") {
    Dataset d = make_test_set(2, 3);
    for (auto& s : d.samples) s.reading.status = ControllerStatus::no_contact;
    CHECK_THROWS_WITH(TrialGenerator(d, space, 1, 5, "t.svad"), Catch::Contains("t.svad") && Catch::Contains("empty"));
  }
  SECTION("an object without readings") {
    Dataset d = make_test_set(2, 3);
    for (auto& s : d.samples)
      if (s.object == 1) s.reading.status = ControllerStatus::no_contact;
    CHECK_THROWS_WITH(TrialGenerator(d, space, 1, 5, "t.svad"), Catch::Contains("obj1"));
  }
  SECTION("NaN position") {
    Dataset d = make_test_set(2, 3);
    d.samples[2].reading.position.y = std::nan("");
    CHECK_THROWS_WITH(TrialGenerator(d, space, 1, 5, "t.svad"), Catch::Contains("sample 2") && Catch::Contains("NaN"));
  }
  SECTION("NaN pressure") {
    Dataset d = make_test_set(2, 3);
    d.samples[1].reading.pressure[7] = std::nanf("");
    CHECK_THROWS_WITH(TrialGenerator(d, space, 1, 5, "t.svad"), Catch::Contains("sample 1") && Catch::Contains("NaN"));
  }
  SECTION("zero readings per trial") {
    Dataset d = make_test_set(2, 3);
    CHECK_THROWS_AS(TrialGenerator(d, space, 1, 0, "t.svad"), Error);
  }
}
