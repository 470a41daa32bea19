// The simulator's exact hit (sim/src/ray_triangle.cpp, object_geometry.cpp):
// Embree finds candidates, the double-precision watertight test decides. Rays
// through shared edges and vertices never slip through, also when the mesh
// repeats its vertices per face; the near-edge flag calls the neighbours in.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <cmath>

#include "../../sim/src/ray_triangle.hpp"
#include "gltf_writer.hpp"

using namespace sva;

namespace {

sim::Mesh to_mesh(const test::TestMesh& t, bool weld) {
  sim::Mesh m;
  for (std::size_t i = 0; i < t.indices.size(); i += 3) {
    if (weld) {
      m.triangles.emplace_back(t.indices[i], t.indices[i + 1], t.indices[i + 2]);
    } else {  // a vertex per face corner, as flat-shaded glTF files store them
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (int k = 0; k < 3; ++k) m.positions.push_back(t.positions[t.indices[i + k]]);
      m.triangles.emplace_back(base, base + 1, base + 2);
    }
  }
  if (weld) m.positions = t.positions;
  m.update_bounds();
  return m;
}

}  // namespace

TEST_CASE("exact hit: the test's distance, the edge flag and a miss") {
  const glm::dvec3 a(0, 0, 0), b(10, 0, 0), c(0, 10, 0), down(0, 0, -1);
  const sim::TriangleTest inside = sim::intersect_triangle({2, 3, 5}, down, a, b, c);
  CHECK(inside.hit);
  CHECK(inside.t == 5.0);
  CHECK_FALSE(inside.near_edge);
  const sim::TriangleTest on_edge = sim::intersect_triangle({5, 0, 5}, down, a, b, c);
  CHECK(on_edge.hit);
  CHECK(on_edge.near_edge);
  const sim::TriangleTest just_out = sim::intersect_triangle({5, -1e-9, 5}, down, a, b, c);
  CHECK_FALSE(just_out.hit);
  CHECK(just_out.near_edge);
  CHECK_FALSE(sim::intersect_triangle({20, 20, 5}, down, a, b, c).hit);
  CHECK_FALSE(sim::intersect_triangle({2, 3, 5}, {1, 0, 0}, a, b, c).hit);  // in the triangle's plane
  CHECK_FALSE(sim::intersect_triangle({2, 3, 5}, {0, 0, 0}, a, b, c).hit);  // no direction
}

TEST_CASE("exact hit: rays through a sphere's edges and vertices all hit, welded or not, at the true distance") {
  const test::TestMesh sphere = test::sphere_mesh(30.0f, 3);
  for (bool weld : {true, false}) {
    sim::ObjectGeometry g(to_mesh(sphere, weld));
    const sim::Mesh& m = g.mesh();
    int rays = 0;
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) {
        // Aimed at a corner and at an edge's midpoint, from outside along the radius.
        const glm::dvec3 p0(m.positions[t[k]]), p1(m.positions[t[(k + 1) % 3]]);
        for (const glm::dvec3 target : {p0, 0.5 * (p0 + p1)}) {
          const glm::dvec3 d = -glm::normalize(target);
          const glm::dvec3 o = target - 50.0 * d;
          const sim::ObjectGeometry::Hit h = g.intersect(o, d, 0.0, 1e3);
          INFO("weld " << weld << " ray " << rays);
          REQUIRE(h.hit);
          CHECK(std::fabs(h.t - 50.0) < 1e-9 * 50.0);
          CHECK(glm::dot(h.normal, target) > 0.0);  // the outward facet normal (mesh winding)
          ++rays;
        }
      }
    CHECK(rays == 6 * static_cast<int>(m.triangles.size()));
  }
}

TEST_CASE("exact hit: a stream of parallel rays gives what single rays give") {
  sim::ObjectGeometry g(to_mesh(test::sphere_mesh(30.0f, 2), false));
  util::Rng rng(5);
  std::vector<glm::dvec3> origins;
  for (int i = 0; i < 200; ++i) origins.push_back({rng.uniform(-35, 35), rng.uniform(-35, 35), 60.0});
  const glm::dvec3 down(0, 0, -1);
  std::vector<sim::ObjectGeometry::Hit> hits;
  g.intersect_parallel(origins, down, 100.0, hits);
  REQUIRE(hits.size() == origins.size());
  int hit = 0;
  for (std::size_t i = 0; i < origins.size(); ++i) {
    const sim::ObjectGeometry::Hit one = g.intersect(origins[i], down, 0.0, 100.0);
    CHECK(one.hit == hits[i].hit);
    CHECK(one.t == hits[i].t);
    CHECK(one.triangle == hits[i].triangle);
    hit += one.hit;
  }
  CHECK(hit > 50);
  CHECK(hit < 200);
}
