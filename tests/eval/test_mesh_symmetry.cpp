// Symmetries found from a mesh (docs/pose-errors.md) on shapes whose groups are known by hand: a cube's 24
// rotations, a box's 4, a cylinder's continuous axis with its half turn, a cone's axis alone, nothing for an
// irregular block; the scene's declared symmetry checked against them; the surface distance they rest on.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include <sva/base/so3.hpp>
#include <sva/error.hpp>
#include <sva/eval/mesh_symmetry.hpp>

#include "eval/surface_distance.hpp"

using namespace sva;
using namespace sva::eval;

namespace {

constexpr double kPi = std::numbers::pi;

ObjectSurface box(double x, double y, double z, glm::vec3 moved_corner = glm::vec3(0.0f)) {
  ObjectSurface s;
  for (int k = 0; k < 8; ++k)
    s.positions.emplace_back((k & 1 ? 0.5 : -0.5) * x, (k & 2 ? 0.5 : -0.5) * y, (k & 4 ? 0.5 : -0.5) * z);
  s.positions[7] += moved_corner;
  // Two triangles per face, counter-clockwise from outside.
  const unsigned q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    s.triangles.emplace_back(f[0], f[1], f[2]);
    s.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return s;
}

// A frustum about z with radii r0 (bottom) and r1 (top), n segments, closed by two caps.
ObjectSurface frustum(double r0, double r1, double h, unsigned n = 96) {
  ObjectSurface s;
  for (unsigned k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    s.positions.emplace_back(r0 * std::cos(a), r0 * std::sin(a), -0.5 * h);
    s.positions.emplace_back(r1 * std::cos(a), r1 * std::sin(a), 0.5 * h);
  }
  const unsigned bottom = 2 * n, top = 2 * n + 1;
  s.positions.emplace_back(0.0, 0.0, -0.5 * h);
  s.positions.emplace_back(0.0, 0.0, 0.5 * h);
  for (unsigned k = 0; k < n; ++k) {
    const unsigned a = 2 * k, b = 2 * ((k + 1) % n);
    s.triangles.emplace_back(a, b, b + 1);
    s.triangles.emplace_back(a, b + 1, a + 1);
    s.triangles.emplace_back(bottom, b, a);
    s.triangles.emplace_back(top, a + 1, b + 1);
  }
  return s;
}

SceneObject object_with(Symmetry symmetry) {
  SceneObject o;
  o.name = "thing";
  o.symmetry = std::move(symmetry);
  return o;
}

Symmetry cyclic_z(int order) {
  Symmetry s;
  s.kind = Symmetry::Kind::discrete;
  for (int k = 0; k < order; ++k) s.rotations.push_back(so3::about_axis({0, 0, 1}, 2.0 * kPi * k / order));
  return s;
}

}  // namespace

TEST_CASE("mesh symmetry: a cube has the 24 rotations of the octahedral group") {
  const MeshSymmetry s = find_symmetries(box(40, 40, 40), "cube");
  CHECK_FALSE(s.axis);
  CHECK(s.rotations.size() == 24);
  CHECK(s.tolerance_mm == Approx(0.01 * 40 * std::sqrt(3.0)).epsilon(1e-6));
  CHECK(s.worst_accepted_mm < 1e-6);  // exact symmetries of exact corners
  CHECK(s.describe().rfind("24 rotations: 4-fold about", 0) == 0);
}

TEST_CASE("mesh symmetry: a box of three different sides has the identity and three half turns") {
  const MeshSymmetry s = find_symmetries(box(40, 30, 20), "box");
  CHECK_FALSE(s.axis);
  REQUIRE(s.rotations.size() == 4);
  for (std::size_t k = 1; k < 4; ++k) CHECK(so3::angle_sincos(s.rotations[k]) == Approx(kPi));
}

TEST_CASE("mesh symmetry: a cylinder is continuous about its axis and turned over, a cone only continuous") {
  const MeshSymmetry cylinder = find_symmetries(frustum(20, 20, 60), "cylinder");
  REQUIRE(cylinder.axis);
  CHECK(std::fabs(cylinder.axis->z) == Approx(1.0).epsilon(1e-9));
  REQUIRE(cylinder.rotations.size() == 2);
  CHECK(glm::dot(cylinder.rotations[1] * glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 1)) == Approx(-1.0).epsilon(1e-6));
  // BOP's discretisation: ceil(pi / 0.01) = 315 turns per discrete symmetry.
  CHECK(symmetry_rotations(cylinder).size() == 2 * 315);

  const MeshSymmetry cone = find_symmetries(frustum(25, 10, 50), "cone");
  REQUIRE(cone.axis);
  CHECK(cone.rotations.size() == 1);
}

TEST_CASE("mesh symmetry: an irregular block has only the identity") {
  const MeshSymmetry s = find_symmetries(box(40, 30, 20, {6.0f, 4.0f, 3.0f}), "block");
  CHECK(s.only_identity());
  CHECK(s.describe() == "none");
  CHECK(symmetry_rotations(s).size() == 1);
}

TEST_CASE("mesh symmetry: the scene's declared symmetry is checked against the mesh's, both ways") {
  const MeshSymmetry cylinder = find_symmetries(frustum(20, 20, 60), "cylinder");
  // Declared none: the mesh's axis and half turn are left out.
  const std::string none = symmetry_disagreement(object_with({}), cylinder);
  CHECK(none.find("\"thing\"") != std::string::npos);
  CHECK(none.find("leaves out every turn about (0.00, 0.00, 1.00) and a half turn") != std::string::npos);
  // Declared axis z: agrees on the axis, still leaves out the half turn.
  Symmetry axis;
  axis.kind = Symmetry::Kind::axis;
  const std::string turned = symmetry_disagreement(object_with(axis), cylinder);
  CHECK(turned.find("leaves out a half turn") != std::string::npos);
  CHECK(turned.find("lacks") == std::string::npos);
  // A box: a declared 4-fold axis it lacks; its own half turns declared as 2-fold about z and about x are not all.
  const MeshSymmetry block = find_symmetries(box(40, 30, 20), "box");
  const std::string four = symmetry_disagreement(object_with(cyclic_z(4)), block);
  CHECK(four.find("lacks 4-fold about (0.00, 0.00, 1.00)") != std::string::npos);
  CHECK(four.find("leaves out 2 of its 4 rotations") != std::string::npos);
  // The irregular block declared none: they agree.
  CHECK(symmetry_disagreement(object_with({}), find_symmetries(box(40, 30, 20, {6.0f, 4.0f, 3.0f}), "b")).empty());
}

TEST_CASE("surface distance: exact to the faces, edges and corners of a box, and the samples lie on the surface") {
  const SurfaceDistance d(box(40, 30, 20), "box");
  CHECK(d.area() == Approx(2 * (40 * 30 + 40 * 20 + 30 * 20)));
  CHECK(d.distance({0, 0, 0}) == Approx(10.0));                    // inside: the nearest face, z = +-10
  CHECK(d.distance({0, 0, 13}) == Approx(3.0));                    // above a face
  CHECK(d.distance({23, 18, 0}) == Approx(std::sqrt(9.0 + 9.0)));  // beside an edge
  CHECK(d.distance({120, 0, 0}) == Approx(100.0));                 // far outside the grid
  CHECK(d.distance({120, 0, 0}, 5.0) >= 5.0);                      // capped: some value past the cap
  CHECK(d.diameter() == Approx(std::sqrt(40.0 * 40 + 30 * 30 + 20 * 20)));
  const auto points = d.sample(300, 1);
  REQUIRE(points.size() == 300);
  for (const auto& p : points) CHECK(d.distance(p) < 1e-9);
  CHECK(points == d.sample(300, 1));  // the same points every time
}

TEST_CASE("surface distance: a mesh without area or with a bad index, or a bad search, is an error naming it") {
  ObjectSurface flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  CHECK_THROWS_WITH(SurfaceDistance(flat, "flat.glb"), Catch::Contains("flat.glb") && Catch::Contains("positive area"));
  ObjectSurface bad = box(1, 1, 1);
  bad.triangles.push_back({0, 1, 99});
  CHECK_THROWS_WITH(find_symmetries(bad, "bad.glb"), Catch::Contains("bad.glb") && Catch::Contains("out of range"));
  SymmetrySearch bad_search;
  bad_search.tolerance_fraction = std::nan("");
  CHECK_THROWS_WITH(find_symmetries(box(1, 1, 1), "box", bad_search), Catch::Contains("tolerance"));
  bad_search = {};
  bad_search.max_order = 1;
  CHECK_THROWS_WITH(find_symmetries(box(1, 1, 1), "box", bad_search), Catch::Contains("order") && Catch::Contains("1"));
  ObjectSurface nan = box(1, 1, 1);
  nan.positions[0].x = std::nanf("");
  CHECK_THROWS_WITH(SurfaceDistance(nan, "nan.glb"), Catch::Contains("nan.glb") && Catch::Contains("not finite"));
}
