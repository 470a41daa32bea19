// The verify stage's measurement model (host/src/estimate/surface_model.cpp): every reading weighed against what the
// object's own mesh predicts, so that identical surfaces give exactly zero evidence and a touch on the region where
// twins differ decides.
#include <catch2/catch.hpp>

#include <sva/base/closest_point.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

#include <cmath>
#include <cstdint>

#include "estimate/fit.hpp"
#include "estimate/heightfield.hpp"
#include "estimate/surface_model.hpp"
#include "estimate/verify.hpp"

using namespace sva;
using sva::test::heightfield;

namespace {

ObservedReading touch(const RigidPose& pose, double x, double y) {
  ObservedReading r;
  r.position = pose.apply(glm::dvec3(x, y, 0.0));
  r.normal = pose.rotate(glm::dvec3(0.0, 0.0, 1.0));
  r.norm_conf = 1.0f;
  r.classes = {{0, 1.0f}};
  return r;
}

RigidPose placed() {
  RigidPose p;
  p.R = so3::exp(glm::dvec3(0.1, -0.2, 0.3));
  p.T = glm::dvec3(12.0, -7.0, 30.0);
  return p;
}

// A closed, finely cut surface: a sphere of 12 mm, 1,600 triangles of about 1 mm (its poles' degenerate ones are
// dropped by the model).
constexpr double kBallRadius = 12.0;
ObjectSurface ball_surface() {
  ObjectSurface ball;
  const int rings = 20, segments = 40;
  const double radius = kBallRadius, pi = std::acos(-1.0);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = pi * i / rings, ph = 2.0 * pi * j / segments;
      ball.positions.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::sin(th) * std::sin(ph),
                                  radius * std::cos(th));
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](int r, int k) { return static_cast<unsigned>(r * segments + (k % segments)); };
      ball.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      ball.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return ball;
}

RefineSettings paper_settings() {  // paper3d's: 8 mm bins
  RefineSettings s;
  s.scale_final_mm = 2.0;
  s.normal_weight_mm = 1.0;
  s.threads = 1;
  return s;
}

// Fits of the leading objects 0 and 1 at poses of their own (their training contacts gave each another pose).
Fits two_fits(const RigidPose& a, const RigidPose& b) {
  Fits f;
  f.leading.resize(2);
  f.leading[0].object = 0, f.leading[0].fine.pose = a;
  f.leading[1].object = 1, f.leading[1].fine.pose = b;
  return f;
}

}  // namespace

TEST_CASE("surface model: two copies of one mesh give exactly zero evidence between them, reading by reading") {
  const SurfaceModel model({heightfield(false), heightfield(false)}, contact_noise(paper_settings()).reach_mm);
  const RigidPose truth = placed();
  RigidPose off = truth;  // the other copy's fit, 0.7 mm and a little turned away
  off.T += glm::dvec3(0.7, 0.0, -0.2);
  off.R = so3::exp(glm::dvec3(0.0, 0.0, 0.03)) * off.R;
  const Fits fits = two_fits(truth, off);
  const SurfaceIndex no_contacts(MapReadings{}, 2);
  std::vector<ObservedReading> readings;
  for (int k = 0; k < 12; ++k) {
    readings.push_back(touch(truth, 2.0 + 3.1 * k, 37.0 - 2.9 * k));
    const Verification v = verify_candidates(fits, readings, no_contacts, paper_settings(), 2, &model);
    REQUIRE(v.log2_fit.size() == 2);
    INFO("after " << readings.size() << " readings");
    CHECK(v.log2_fit[0] == v.log2_fit[1]);  // bit for bit, whichever fit each object's contacts gave
    CHECK(v.log2_fit[0] > -0.5 * static_cast<double>(readings.size()));  // and both explain the touches
  }
}

TEST_CASE("surface model: a touch on the region where twins differ decides, a touch elsewhere moves nothing") {
  const SurfaceModel model({heightfield(false), heightfield(true)}, contact_noise(paper_settings()).reach_mm);
  const ContactNoise noise = contact_noise(paper_settings());
  const RigidPose truth = placed();  // the flat twin (object 0) is touched, its pose known
  const double on_region = model.log2_likelihood(0, touch(truth, 20.0, 20.0), truth, noise) -
                           model.log2_likelihood(1, touch(truth, 20.0, 20.0), truth, noise);
  CHECK(on_region >= std::log2(99.0));  // the truth >= 0.99 from an even prior, after that one touch
  for (const glm::dvec2 xy : {glm::dvec2(2.0, 3.0), glm::dvec2(36.0, 5.5), glm::dvec2(4.0, 38.0)}) {
    const ObservedReading r = touch(truth, xy.x, xy.y);
    const double elsewhere = model.log2_likelihood(0, r, truth, noise) - model.log2_likelihood(1, r, truth, noise);
    INFO("at " << xy.x << ", " << xy.y);
    CHECK(std::fabs(elsewhere) < 0.1);
  }
}

TEST_CASE("surface model: the nearest point is the closest on any triangle, ties to the smaller index") {
  const SurfaceModel model({heightfield(false)}, 4.0);
  const SurfaceModel::Nearest above = model.nearest(0, {12.5, 17.5, 1.5}, 4.0);
  REQUIRE(above.found);
  CHECK(above.distance == Approx(1.5));
  CHECK(above.point.z == Approx(0.0).margin(1e-12));
  CHECK(above.normal.z == Approx(1.0));
  // Off the edge of the field: the edge itself, 2 mm away; beyond the reach, nothing.
  const SurfaceModel::Nearest edge = model.nearest(0, {-2.0, 10.0, 0.0}, 4.0);
  REQUIRE(edge.found);
  CHECK(edge.distance == Approx(2.0));
  CHECK_FALSE(model.nearest(0, {20.0, 20.0, 9.0}, 4.0).found);
  // A vertex shared by six triangles: the smallest index among them, whatever order the tree holds them in.
  const SurfaceModel::Nearest corner = model.nearest(0, {10.0, 10.0, 0.5}, 4.0);
  REQUIRE(corner.found);
  CHECK(corner.triangle == 2 * (1 * 8 + 1));  // the first triangle of cell (1, 1), which holds vertex (2, 2)
}

TEST_CASE("surface model: the nearest point found through the tree is the search of every triangle's") {
  // Queries in and around the ball: the boxes visited nearest first and those past the best so far passed over must
  // give the smallest (distance, index) of all triangles within the radius, bit for bit.
  const ObjectSurface ball = ball_surface();
  const double radius = kBallRadius;
  const SurfaceModel model({ball}, 4.0);
  util::Rng rng(11);
  std::size_t found = 0;
  for (int k = 0; k < 3000; ++k) {
    const glm::dvec3 dir = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const glm::dvec3 p = dir * (radius + 6.0 * rng.uniform() - 3.0);
    const double reach = k % 3 == 0 ? 1.0 : 4.0;
    // Every triangle, the smallest (squared distance, index) within the reach.
    double best_d2 = reach * reach;
    std::int64_t best = -1;
    for (std::size_t t = 0; t < ball.triangles.size(); ++t) {
      const glm::uvec3 tri = ball.triangles[t];
      const glm::dvec3 a(ball.positions[tri.x]), b(ball.positions[tri.y]), c(ball.positions[tri.z]);
      if (!(glm::length(glm::cross(b - a, c - a)) > 0.0)) continue;  // the poles' degenerate triangles
      const glm::dvec3 q = closest_on_triangle(p, a, b, c);
      const double d2 = glm::dot(q - p, q - p);
      if (d2 < best_d2) best_d2 = d2, best = static_cast<std::int64_t>(t);
    }
    const SurfaceModel::Nearest got = model.nearest(0, p, reach);
    INFO("query " << k << " at (" << p.x << ", " << p.y << ", " << p.z << "), reach " << reach);
    REQUIRE(got.found == (best >= 0));
    if (best < 0) continue;
    ++found;
    CHECK(got.triangle == static_cast<std::uint32_t>(best));
    CHECK(got.distance == std::sqrt(best_d2));
  }
  CHECK(found > 1500);  // most queries lie within the reach
}

TEST_CASE("surface model: the nearest point within a smaller radius follows from the one within a larger") {
  // The fine pose weighs the same pose again at its next, smaller scale: it keeps the last scale's matches, less those
  // within() leaves out, without a search (estimate/fine_pose.cpp, Problem::narrowed). That must be the search's own
  // answer, bit for bit: at a fraction of the radius, at the found distance itself (the edge: strictly within), and
  // from a radius past the reach.
  const SurfaceModel model({ball_surface()}, 3.0);
  util::Rng rng(12);
  std::size_t kept = 0, dropped = 0;
  for (int k = 0; k < 2000; ++k) {
    const double x = rng.normal(), y = rng.normal(), z = rng.normal();  // drawn in order on every compiler
    const double depth = 6.0 * rng.uniform() - 3.0, wide = 0.5 + 4.0 * rng.uniform();
    const glm::dvec3 p = glm::normalize(glm::dvec3(x, y, z)) * (kBallRadius + depth);
    const SurfaceModel::Nearest first = model.nearest(0, p, wide);
    const double at = first.found ? first.distance : 0.5 * wide;
    for (const double narrow :
         {wide, 0.75 * wide, 0.5 * wide, 0.25 * wide, at, std::nextafter(at, 0.0), std::nextafter(at, 10.0)}) {
      INFO("query " << k << ", radius " << wide << " then " << narrow);
      const SurfaceModel::Nearest again = model.nearest(0, p, narrow);
      const bool follows = first.found && model.within(first.d2, narrow);
      REQUIRE(again.found == follows);
      if (!follows) {
        ++dropped;
        continue;
      }
      ++kept;
      CHECK(again.triangle == first.triangle);
      CHECK(again.d2 == first.d2);
      CHECK(again.point == first.point);
    }
  }
  CHECK(kept > 2000);  // not vacuous: both answers are common
  CHECK(dropped > 2000);
}

TEST_CASE("surface model: a triangle far larger than the reach is searched as any other, a broken one refused") {
  // A letter's face is hundreds of mm across against a reach of half a millimetre: one entry of the tree, found.
  ObjectSurface huge;
  huge.positions = {{0, 0, 0}, {9e5f, 0, 0}, {0, 9e5f, 0}};
  huge.triangles = {{0, 1, 2}};
  const SurfaceModel model({huge}, 0.5);
  const SurfaceModel::Nearest on = model.nearest(0, {1000.0, 2000.0, 0.25}, 0.5);
  REQUIRE(on.found);
  CHECK(on.distance == Approx(0.25));
  CHECK_FALSE(model.nearest(0, {1000.0, 2000.0, 0.75}, 0.5).found);
  ObjectSurface broken = huge;
  broken.positions[1].y = std::nanf("");
  CHECK_THROWS_WITH(SurfaceModel({broken}, 0.5),
                    Catch::Contains("triangle 0 of object 0") && Catch::Contains("not finite"));
  broken = huge;
  broken.triangles = {{0, 1, 3}};
  CHECK_THROWS_WITH(SurfaceModel({broken}, 0.5),
                    Catch::Contains("triangle 0 of object 0") && Catch::Contains("vertex"));
  CHECK_THROWS_WITH(SurfaceModel({huge}, 0.0), Catch::Contains("reach"));
}

TEST_CASE("surface model: a pose a little off is polished onto the mesh before it is scored") {
  const SurfaceModel model({heightfield(true)}, contact_noise(paper_settings()).reach_mm);
  const ContactNoise noise = contact_noise(paper_settings());
  const RigidPose truth = placed();
  std::vector<ObservedReading> readings;  // the plateau's top and the flat around it, 9 touches
  for (double x : {4.0, 20.0, 36.0})
    for (double y : {4.0, 20.0, 36.0}) {
      ObservedReading r = touch(truth, x, y);
      if (x == 20.0 && y == 20.0) r.position = truth.apply(glm::dvec3(x, y, 6.0));
      readings.push_back(r);
    }
  RigidPose start = truth;  // the training contacts' fit: 0.8 mm high and 2.3 degrees tilted
  start.T += truth.rotate(glm::dvec3(0.0, 0.0, 0.8));
  start.R = so3::exp(truth.rotate(glm::dvec3(0.04, 0.0, 0.0))) * start.R;
  const RigidPose polished = polish_on_mesh(model, 0, readings, start, paper_settings(), noise);
  const double before = model.log2_likelihood(0, readings, start, noise);
  const double after = model.log2_likelihood(0, readings, polished, noise);
  CHECK(after > before + 1.0);
  for (const ObservedReading& r : readings) {  // every contact back on its facet
    const glm::dvec3 p = glm::transpose(polished.R) * (r.position - polished.T);
    const SurfaceModel::Nearest q = model.nearest(0, p, noise.reach_mm);
    REQUIRE(q.found);
    CHECK(q.distance < 0.05);
  }
  // Too few readings to pose anything: the start stands, untouched.
  const RigidPose kept = polish_on_mesh(model, 0, std::span(readings).first(3), start, paper_settings(), noise);
  CHECK(kept.T == start.T);
  CHECK(kept.R == start.R);
}

TEST_CASE("surface model: the pad's image tells twins apart where the contact point and normal agree") {
  PadGeometry pad;  // the 6 x 6 array at 2 mm of the built-in scenes, 2 kPa at 100 kPa/mm to count as touching
  pad.rows = pad.cols = 6, pad.pitch_mm = 2.0, pad.contact_depth_mm = 0.02;
  const double reach = contact_noise(paper_settings()).reach_mm;
  const SurfaceModel model({heightfield(false), heightfield(true)}, reach, pad);
  const RigidPose truth = placed();  // the flat twin is touched beside the raised twin's slope (it rises from x = 10)
  ObservedReading r = touch(truth, 7.0, 20.0);
  r.x_axis = truth.rotate(glm::dvec3(1.0, 0.0, 0.0));
  r.depth_mm.assign(36, 0.2f);  // the flat pressed evenly: the columns at x = 2..12 all felt it
  ContactNoise with_pad = contact_noise(paper_settings());
  with_pad.pad_sigma_mm = 0.04;
  ContactNoise without_pad = with_pad;
  without_pad.pad_sigma_mm = 0.0;
  // The contact alone: the raised twin is flat at (7, 20) too, so the point and normal say nothing.
  CHECK(std::fabs(model.log2_likelihood(0, r, truth, without_pad) - model.log2_likelihood(1, r, truth, without_pad)) <
        0.1);
  // The image: the raised twin's slope would press the pad's last column 2.4 mm deep; the flat one fits it.
  CHECK(model.pad_misfit(0, r, truth) < 0.01);
  CHECK(model.pad_misfit(1, r, truth) > 0.1);
  CHECK(model.log2_likelihood(0, r, truth, with_pad) - model.log2_likelihood(1, r, truth, with_pad) >= std::log2(99.0));
  // Copies of one mesh: the image's evidence between them is exactly zero.
  const SurfaceModel copies({heightfield(true), heightfield(true)}, reach, pad);
  CHECK(copies.log2_likelihood(0, r, truth, with_pad) == copies.log2_likelihood(1, r, truth, with_pad));
  // No image (a planner's prediction), or one of another size: nothing to compare, the contact alone.
  ObservedReading bare = r;
  bare.depth_mm.clear();
  CHECK(model.pad_misfit(1, bare, truth) < 0.0);
  CHECK(model.log2_likelihood(1, bare, truth, with_pad) == model.log2_likelihood(1, bare, truth, without_pad));
  bare.depth_mm.assign(16, 0.2f);
  CHECK(model.pad_misfit(1, bare, truth) < 0.0);
  // A pad without rows is refused by name.
  PadGeometry none;
  CHECK_THROWS_WITH(SurfaceModel({heightfield(false)}, reach, none), Catch::Contains("the pad needs rows"));
}

TEST_CASE("surface check: every object polished from every leading start, side by side, gives the bits in turn gives") {
  // verify_candidates runs its leading objects x starts polishes as one task each (issue 52: a many-core host had one
  // worker per object). The bits must be each object's best start by the contacts, then that pose with the pad, for
  // any thread count: computed here one object and one start at a time.
  PadGeometry pad;
  pad.rows = pad.cols = 6, pad.pitch_mm = 2.0, pad.contact_depth_mm = 0.02;
  const SurfaceModel model({heightfield(false), heightfield(true), heightfield(true)},
                           contact_noise(paper_settings()).reach_mm, pad);
  const RigidPose truth = placed();
  std::vector<RigidPose> starts(3, truth);  // each leading object's fit from its contacts, each a little off
  starts[1].T += glm::dvec3(0.9, -0.4, 0.3);
  starts[2].R = so3::exp(glm::dvec3(0.02, -0.03, 0.05)) * starts[2].R;
  Fits fits;
  fits.leading.resize(3);
  for (std::uint32_t i = 0; i < 3; ++i) fits.leading[i].object = 2 - i, fits.leading[i].fine.pose = starts[i];
  std::vector<ObservedReading> readings;
  for (int k = 0; k < 10; ++k) {
    ObservedReading r = touch(truth, 3.0 + 3.4 * k, 35.0 - 3.1 * k);
    r.x_axis = truth.rotate(glm::dvec3(1.0, 0.0, 0.0));
    r.depth_mm.assign(36, 0.1f + 0.01f * static_cast<float>(k));
    readings.push_back(r);
  }
  ContactNoise noise = contact_noise(paper_settings());
  noise.pad_sigma_mm = kPadSigmaMm;
  ContactNoise contacts = noise;
  contacts.pad_sigma_mm = 0.0;
  std::vector<double> expected(3, 0.0);
  for (std::uint32_t o = 0; o < 3; ++o) {
    double best = 0.0;
    RigidPose best_pose;
    for (std::size_t j = 0; j < 3; ++j) {
      const RigidPose p = polish_on_mesh(model, o, readings, starts[j], paper_settings(), contacts);
      const double b = model.log2_likelihood(o, readings, p, contacts);
      if (j == 0 || b > best) best = b, best_pose = p;
    }
    expected[o] = model.log2_likelihood(o, readings, best_pose, noise);
  }
  const SurfaceIndex no_contacts(MapReadings{}, 3);
  for (unsigned threads : {1u, 3u}) {
    INFO(threads << " threads");
    RefineSettings s = paper_settings();
    s.threads = threads;
    const Verification v = verify_candidates(fits, readings, no_contacts, s, 3, &model);
    REQUIRE(v.log2_fit.size() == 3);
    for (std::uint32_t o = 0; o < 3; ++o) CHECK(v.log2_fit[o] == expected[o]);
  }
  CHECK(expected[0] != expected[1]);  // not vacuous: the flat and raised twins score apart
}
