// The verify stage's measurement model (host/src/estimate/surface_model.cpp): every reading weighed against what the
// object's own mesh predicts, so that identical surfaces give exactly zero evidence and a touch on the region where
// twins differ decides.
#include <catch2/catch.hpp>

#include <sva/base/so3.hpp>

#include <cmath>

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
  // A vertex shared by six triangles: the smallest index among them, whatever order the cells hold them in.
  const SurfaceModel::Nearest corner = model.nearest(0, {10.0, 10.0, 0.5}, 4.0);
  REQUIRE(corner.found);
  CHECK(corner.triangle == 2 * (1 * 8 + 1));  // the first triangle of cell (1, 1), which holds vertex (2, 2)
}

TEST_CASE("surface model: a mesh far larger than its cells is refused, not gridded into all memory") {
  ObjectSurface huge;
  huge.positions = {{0, 0, 0}, {9e5f, 0, 0}, {0, 9e5f, 9e5f}};
  huge.triangles = {{0, 1, 2}};
  CHECK_THROWS_WITH(SurfaceModel({huge}, 0.5), Catch::Contains("triangle 0 of object 0") && Catch::Contains("cells"));
  CHECK_NOTHROW(SurfaceModel({heightfield(true)}, 0.5));  // a 40 mm field at half-millimetre cells is fine
}
