// Metrics against hand-computed cases: Eq 22 with an axis and with a discrete
// group, the inertial distance formula, order statistics.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include <sva/base/rng.hpp>
#include <sva/eval/results.hpp>
#include <sva/eval/trials.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>
#include <sva/sim/simulate.hpp>

#include <sva/base/so3.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include "eval/metrics.hpp"
#include "eval/surface_distance.hpp"
#include "map/map_access.hpp"
#include "map/map_file.hpp"
#include "map/pair_map.hpp"
#include "test_support.hpp"
#include "training/session_sampling.hpp"

using namespace sva;
using namespace sva::eval;

namespace {

glm::dmat3 rot(double angle, glm::dvec3 axis) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)));
}

Symmetry axis_symmetry(glm::dvec3 axis) {
  Symmetry s;
  s.kind = Symmetry::Kind::axis;
  s.axis = glm::normalize(axis);
  return s;
}

Symmetry cyclic(int order, glm::dvec3 axis) {
  Symmetry s;
  s.kind = Symmetry::Kind::discrete;
  s.axis = axis;
  for (int k = 0; k < order; ++k) s.rotations.push_back(rot(2.0 * std::numbers::pi * k / order, axis));
  return s;
}

// Eq 22 by brute force: the smallest angle over a fine sweep about the axis.
double brute_axis_error(const glm::dmat3& R, const glm::dmat3& Rh, glm::dvec3 axis) {
  double best = 10.0;
  for (int k = 0; k < 20000; ++k) {
    double g = 2.0 * std::numbers::pi * k / 20000;
    best = std::min(best, so3::angle_sincos(glm::transpose(Rh) * R * rot(g, axis)));
  }
  return best;
}

}  // namespace

TEST_CASE("angular error without symmetry is the angle of R R_hat^T") {
  glm::dmat3 R = rot(0.7, {1, 2, 3});
  glm::dmat3 Rh = R * rot(0.25, {0, 1, 0});
  CHECK(angular_error(R, Rh, Symmetry{}) == Approx(0.25).margin(1e-12));
  CHECK(angular_error(R, R, Symmetry{}) == Approx(0.0).margin(1e-12));
  // Symmetric in its arguments.
  CHECK(angular_error(Rh, R, Symmetry{}) == Approx(0.25).margin(1e-12));
}

TEST_CASE("Eq 22 with an axis: a rotation about the symmetry axis has zero error") {
  const glm::dvec3 zeta(0.2, -0.4, 1.0);
  const Symmetry sym = axis_symmetry(zeta);
  glm::dmat3 R = rot(1.1, {0.5, 0.5, -0.2});
  for (double g : {0.1, 1.0, 2.5, std::numbers::pi, -2.0}) {
    // The estimate differs from the truth only by a spin about the object's axis.
    glm::dmat3 Rh = R * rot(g, zeta);
    CHECK(angular_error(R, Rh, sym) == Approx(0.0).margin(1e-6));
    CHECK(angular_error(R, Rh, Symmetry{}) == Approx(std::abs(g)).margin(1e-9));
  }
  // A tilt of the axis cannot be explained away: 0.3 rad about a perpendicular axis stays 0.3.
  glm::dvec3 perp = glm::normalize(glm::cross(zeta, glm::dvec3(1, 0, 0)));
  CHECK(angular_error(R, R * rot(0.3, perp) * rot(1.7, zeta), sym) == Approx(0.3).margin(1e-6));
}

TEST_CASE("Eq 22 closed form agrees with a brute-force sweep about the axis") {
  util::Rng rng(7, 1);
  const glm::dvec3 zeta(0, 0, 1);
  for (int i = 0; i < 25; ++i) {
    glm::dmat3 R = uniform_rotation(rng), Rh = uniform_rotation(rng);
    CHECK(angular_error(R, Rh, axis_symmetry(zeta)) == Approx(brute_axis_error(R, Rh, zeta)).margin(2e-3));
  }
}

TEST_CASE("the letter I: its 180-degree rotation has zero error, 90 degrees does not") {
  const Symmetry letter_i = cyclic(2, {0, 0, 1});
  glm::dmat3 R = rot(0.4, {0, 0, 1});
  CHECK(angular_error(R, R * rot(std::numbers::pi, {0, 0, 1}), letter_i) == Approx(0.0).margin(1e-9));
  CHECK(angular_error(R, R * rot(std::numbers::pi / 2, {0, 0, 1}), letter_i) ==
        Approx(std::numbers::pi / 2).margin(1e-9));
  // 170 degrees is 10 degrees from the symmetric pose.
  CHECK(angular_error(R, R * rot(170.0 * std::numbers::pi / 180, {0, 0, 1}), letter_i) ==
        Approx(10.0 * std::numbers::pi / 180).margin(1e-9));
}

TEST_CASE("the letter O: any in-plane rotation has zero error") {
  const Symmetry letter_o = axis_symmetry({0, 0, 1});
  PoseSpaceSpec planar;
  planar.kind = PoseSpaceSpec::Kind::planar;
  util::Rng rng(3, 2);
  for (int i = 0; i < 50; ++i) {
    RigidPose a = random_pose(rng, planar), b = random_pose(rng, planar);
    CHECK(angular_error(a.R, b.R, letter_o) == Approx(0.0).margin(1e-6));
  }
}

TEST_CASE("inertial distance follows sqrt(|dT|^2 + 4/5 r^2 (1 - cos theta))") {
  CHECK(inertial_distance(3.0, 0.0, 40.0) == Approx(3.0));
  // theta = 90 degrees, r = 40: 4/5 * 1600 = 1280; with dT = 4: sqrt(16 + 1280) = 36.
  CHECK(inertial_distance(4.0, std::numbers::pi / 2, 40.0) == Approx(36.0));
  // theta = 180 degrees, no translation: sqrt(8/5) r.
  CHECK(inertial_distance(0.0, std::numbers::pi, 10.0) == Approx(std::sqrt(1.6) * 10.0));
  RigidPose truth{rot(0.5, {1, 0, 0}), {10, 20, 30}};
  RigidPose est{truth.R * rot(std::numbers::pi / 2, {0, 1, 0}), truth.T + glm::dvec3(0, 3, 4)};
  PoseError e = pose_error(truth, est, Symmetry{}, 40.0);
  CHECK(e.translation_mm == Approx(5.0));
  CHECK(e.angular_rad == Approx(std::numbers::pi / 2));
  CHECK(e.inertial_mm == Approx(std::sqrt(25.0 + 1280.0)));
}

TEST_CASE("median and percentile") {
  CHECK_FALSE(median({}).has_value());
  CHECK(*median({5.0}) == 5.0);
  CHECK(*median({4.0, 1.0, 3.0}) == 3.0);
  CHECK(*median({4.0, 1.0, 3.0, 2.0}) == 2.5);
  std::vector<double> v;
  for (int i = 0; i <= 100; ++i) v.push_back(100 - i);
  CHECK(*percentile(v, 95.0) == Approx(95.0));
  CHECK(*percentile(v, 0.0) == 0.0);
  CHECK(*percentile(v, 100.0) == 100.0);
}

// --- Symmetry axes through any point (the translational error), and mean / p90 beside the median.

namespace {

Symmetry through(Symmetry s, glm::dvec3 point) {
  s.point = point;
  return s;
}

// The truth composed with a symmetry S about the axis through p: x -> S (x - p) + p in the object frame.
RigidPose symmetric_copy(const RigidPose& truth, const glm::dmat3& S, glm::dvec3 p) {
  RigidPose sym;
  sym.R = S;
  sym.T = p - S * p;
  return truth * sym;
}

}  // namespace

TEST_CASE("an axis through a point: the copy turned about it is right in translation and angle") {
  RigidPose truth;
  truth.R = rot(0.7, {1.0, 2.0, -0.5});
  truth.T = {30.0, -12.0, 55.0};
  const glm::dvec3 p(15.0, -4.0, 0.0);
  const Symmetry s = through(axis_symmetry({0.0, 0.0, 1.0}), p);
  for (double g : {0.3, 1.5, 3.0}) {
    const RigidPose est = symmetric_copy(truth, rot(g, {0.0, 0.0, 1.0}), p);
    INFO("turn " << g);
    CHECK(translation_error(truth, est, s) < 1e-9);
    CHECK(angular_error(truth.R, est.R, s) < 1e-6);
    const PoseError e = pose_error(truth, est, s, 40.0);
    CHECK(e.translation_mm < 1e-9);
    // The same estimate against an axis through the origin: the lever arm |p - S p| shows as translation error.
    const Symmetry at_origin = axis_symmetry({0.0, 0.0, 1.0});
    CHECK(translation_error(truth, est, at_origin) == Approx(glm::length(p - rot(g, {0.0, 0.0, 1.0}) * p)));
  }
  // A real error on top of the turn is still measured in full: 2 mm along the world x.
  RigidPose est = symmetric_copy(truth, rot(1.1, {0.0, 0.0, 1.0}), p);
  est.T += glm::dvec3(2.0, 0.0, 0.0);
  CHECK(translation_error(truth, est, s) == Approx(2.0).margin(1e-9));
}

TEST_CASE("a cyclic group through a point: its elements are right in translation, other turns are not") {
  RigidPose truth;
  truth.R = rot(-1.2, {0.3, -1.0, 0.4});
  truth.T = {-40.0, 5.0, 12.0};
  const glm::dvec3 p(0.0, 10.0, 3.0);
  const Symmetry s = through(cyclic(2, {1.0, 0.0, 0.0}), p);
  const RigidPose half = symmetric_copy(truth, rot(std::numbers::pi, {1.0, 0.0, 0.0}), p);
  CHECK(translation_error(truth, half, s) < 1e-9);
  CHECK(angular_error(truth.R, half.R, s) < 1e-6);
  const RigidPose quarter = symmetric_copy(truth, rot(0.5 * std::numbers::pi, {1.0, 0.0, 0.0}), p);
  CHECK(translation_error(truth, quarter, s) > 1.0);  // not a symmetry: measured against the truth itself
  CHECK(translation_error(truth, quarter, s) == Approx(glm::length(quarter.T - truth.T)));
  // No symmetry: the plain distance, whatever the point.
  Symmetry none;
  none.point = p;
  CHECK(translation_error(truth, half, none) == Approx(glm::length(half.T - truth.T)));
}

TEST_CASE("closest_symmetry attains Eq 22's minimum") {
  util::Rng rng(17);
  const Symmetry s = axis_symmetry({0.2, -0.4, 1.0});
  for (int i = 0; i < 20; ++i) {
    const glm::dmat3 R = rot(rng.uniform(0.0, 3.0), {rng.normal(), rng.normal(), rng.normal()});
    const glm::dmat3 Rh = rot(rng.uniform(0.0, 3.0), {rng.normal(), rng.normal(), rng.normal()});
    const glm::dmat3 S = closest_symmetry(R, Rh, s);
    CHECK(so3::angle_sincos(glm::transpose(R * S) * Rh) == Approx(angular_error(R, Rh, s)).margin(1e-7));
    CHECK(so3::angle_sincos(glm::transpose(S) * S) < 1e-9);  // a rotation
  }
}

TEST_CASE("mean and 90th percentile beside the median") {
  CHECK_FALSE(mean({}).has_value());
  CHECK(*mean({1.0, 2.0, 6.0}) == 3.0);
  std::vector<double> v;
  for (int i = 10; i >= 0; --i) v.push_back(i);  // 0..10, unsorted
  const Spread s = spread_of(v);
  CHECK(*s.median == 5.0);
  CHECK(*s.mean == 5.0);
  CHECK(*s.p90 == Approx(9.0));
  const Spread empty = spread_of({});
  CHECK_FALSE(empty.median.has_value());
  CHECK_FALSE(empty.mean.has_value());
  CHECK_FALSE(empty.p90.has_value());
}

TEST_CASE("the scene's symmetry point: parsed, written back only when set, refused when malformed") {
  auto scene = [](const std::string& symmetry) {
    return R"({"name": "pt", "objects": [{"name": "cup", "mesh": "cup.glb", "symmetry": )" + symmetry + "}]}";
  };
  const Scene with = parse_scene(scene(R"({"type": "axis", "axis": [0, 0, 1], "point": [5, -2.5, 0]})"), "pt.json");
  REQUIRE(with.objects[0].symmetry.kind == Symmetry::Kind::axis);
  CHECK(with.objects[0].symmetry.point == glm::dvec3(5.0, -2.5, 0.0));
  const Scene again = parse_scene(scene_to_json(with), "again.json");
  CHECK(again.objects[0].symmetry.point == glm::dvec3(5.0, -2.5, 0.0));
  const Scene without = parse_scene(scene(R"({"type": "cyclic", "order": 2})"), "pt.json");
  CHECK(without.objects[0].symmetry.point == glm::dvec3(0.0));
  CHECK(scene_to_json(without).find("point") == std::string::npos);  // scene hashes of older scenes unchanged
  CHECK_THROWS_WITH(parse_scene(scene(R"({"type": "axis", "point": [1, 2]})"), "bad.json"),
                    Catch::Contains("bad.json") && Catch::Contains("point"));
  CHECK_THROWS_WITH(parse_scene(scene(R"({"type": "axis", "point": [1, "x", 2]})"), "bad.json"),
                    Catch::Contains("point[1]"));
}

TEST_CASE("the symmetry point travels into the map (version 3), older maps read it as the origin") {
  sim::SimulateOptions so;
  so.train_per_object = 12;
  so.test_per_object = 1;
  TrainOptions to;
  to.clusters = 3;
  PairMap m = MapAccess::pair_map(Map::train(sim::simulate(load_scene("tiny"), so).train, to));
  m.objects[1].symmetry.point = {1.5, -2.0, 7.25};
  const auto dir = test::temp_dir("map-symmetry-point");
  save_pair_map(m, dir / "v3.svam");
  CHECK(load_pair_map(dir / "v3.svam")->objects[1].symmetry.point == glm::dvec3(1.5, -2.0, 7.25));
  write_pair_map(m, dir / "v2.svam", 2);  // the version-2 layout has no point
  CHECK(load_pair_map(dir / "v2.svam")->objects[1].symmetry.point == glm::dvec3(0.0));
  m.objects[1].symmetry.point.y = std::nan("");
  CHECK_THROWS_WITH(save_pair_map(m, dir / "nan.svam"), Catch::Contains("symmetry point"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("readings until the true object holds 95%: per trial, a trial that never gets there counts as M + 1") {
  sva::eval::EvalResult r;
  r.max_readings = 3;
  for (const std::vector<double>& probs :
       {std::vector<double>{0.5, 0.96, 1.0}, std::vector<double>{0.1, 0.2, 0.3}, std::vector<double>{0.95, 0.9, 1.0}}) {
    sva::eval::TrialResult t;
    for (double p : probs) {
      sva::eval::StepResult s;
      s.true_object_probability = p;
      t.steps.push_back(s);
    }
    r.trials.push_back(t);
  }
  const sva::eval::Confidence c = sva::eval::readings_to_confidence(r, 0.95);
  CHECK(c.trials == 3);
  CHECK(c.reached == 2);
  CHECK(*c.mean == Approx((2.0 + 4.0 + 1.0) / 3.0));
  CHECK(*c.median == Approx(2.0));
  CHECK(sva::eval::summarize(r).to_95.reached == 2);
  CHECK_FALSE(sva::eval::readings_to_confidence(sva::eval::EvalResult{}, 0.95).mean.has_value());
}

// MSSD and ADD-S (docs/pose-errors.md) on shapes whose symmetries are known by hand.
namespace {

ObjectSurface three_sided_box() {  // 40 x 30 x 20 mm: the identity and three half turns
  ObjectSurface s;
  for (int k = 0; k < 8; ++k)
    s.positions.emplace_back(k & 1 ? 20.0f : -20.0f, k & 2 ? 15.0f : -15.0f, k & 4 ? 10.0f : -10.0f);
  const unsigned q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    s.triangles.emplace_back(f[0], f[1], f[2]);
    s.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return s;
}

}  // namespace

TEST_CASE("metrics: MSSD of a symmetric half turn is 0 while the angle error is 180 degrees, and ADD-S <= MSSD") {
  const ObjectSurface surface = three_sided_box();
  const MeshSymmetry found = find_symmetries(surface, "box");
  REQUIRE(found.rotations.size() == 4);
  const SurfaceDistance distance(surface, "box");
  const std::vector<glm::dvec3> points = distance.sample(500, 2);
  const std::vector<glm::dmat3> symmetries = symmetry_rotations(found);
  util::Rng rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    RigidPose truth;
    truth.R = so3::exp({rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)});
    truth.T = {rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
    RigidPose flipped = truth;
    flipped.R = truth.R * rot(std::numbers::pi, {0, 0, 1});  // the box turned half about its z axis
    CHECK(angular_error(truth.R, flipped.R, Symmetry{}) == Approx(std::numbers::pi));
    CHECK(mssd(truth, flipped, points, symmetries, found.centre) < 1e-9);
    CHECK(adds(truth, flipped, points, distance) < 1e-9);
    // A pose that is simply wrong: both errors positive, the mean closest-point distance at most the largest.
    RigidPose wrong = truth;
    wrong.R = truth.R * so3::exp({rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)});
    wrong.T += glm::dvec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const double m = mssd(truth, wrong, points, symmetries, found.centre);
    const double a = adds(truth, wrong, points, distance);
    CHECK(m > 0.0);
    CHECK(a <= m + 1e-12);
  }
}

TEST_CASE("metrics: MSSD and ADD-S by hand") {
  // Two points, no symmetry: a pure shift of (3, 4, 0) moves every point 5 mm.
  const std::vector<glm::dvec3> points = {{10, 0, 0}, {0, 10, 0}};
  RigidPose truth, shifted;
  shifted.T = {3, 4, 0};
  CHECK(mssd(truth, shifted, points, {glm::dmat3(1.0)}, glm::dvec3(0.0)) == Approx(5.0));
  // A half turn about z through the origin: (10,0,0) lands 20 mm away; with that half turn a symmetry, 0.
  RigidPose turned;
  turned.R = rot(std::numbers::pi, {0, 0, 1});
  CHECK(mssd(truth, turned, points, {glm::dmat3(1.0)}, glm::dvec3(0.0)) == Approx(20.0));
  CHECK(mssd(truth, turned, points, {glm::dmat3(1.0), rot(std::numbers::pi, {0, 0, 1})}, glm::dvec3(0.0)) ==
        Approx(0.0).margin(1e-12));
  // About a centre off the origin, the copy's translation follows: S about c maps c to itself.
  const glm::dvec3 c{5, 0, 0};
  RigidPose about_c;
  about_c.R = rot(std::numbers::pi, {0, 0, 1});
  about_c.T = c - about_c.R * c;  // the half turn about the axis through c
  CHECK(mssd(truth, about_c, points, {glm::dmat3(1.0), rot(std::numbers::pi, {0, 0, 1})}, c) ==
        Approx(0.0).margin(1e-12));
  // ADD-S: the box's points moved 3 mm out along +z: those on the top face are 3 mm off it, the others keep a
  // nearer face only where one lies within 3 mm; the mean is between 0 and 3.
  const SurfaceDistance box(three_sided_box(), "box");
  RigidPose up;
  up.T = {0, 0, 3};
  const double a = adds(truth, up, box.sample(400, 3), box);
  CHECK(a > 0.0);
  CHECK(a < 3.0);
  CHECK(adds(truth, truth, box.sample(400, 3), box) < 1e-9);
}
