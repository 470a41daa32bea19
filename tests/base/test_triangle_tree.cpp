// The nearest triangle through the tree (sva/base/triangle_tree.hpp) against a search of every triangle: the smallest
// (squared distance, index) within the radius, bit for bit, on meshes whose triangles are tiny, huge, repeated and
// stacked, for queries on, near, inside and far from them.
#include <catch2/catch.hpp>

#include <sva/base/closest_point.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/triangle_tree.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>
#include <vector>

using namespace sva;

namespace {

using Tri = TriangleTree::Triangle;

TriangleTree::Hit every_triangle(const std::vector<Tri>& mesh, const glm::dvec3& p, double radius) {
  TriangleTree::Hit best;
  best.d2 = radius * radius;
  for (const Tri& t : mesh) {
    const glm::dvec3 q = closest_on_triangle(p, glm::dvec3(t.a), glm::dvec3(t.b), glm::dvec3(t.c));
    const double d2 = glm::dot(q - p, q - p);
    if (d2 < best.d2 || (d2 == best.d2 && best.found && t.index < best.index))
      best.found = true, best.index = t.index, best.point = q, best.d2 = d2;
  }
  return best;
}

// A mix that a uniform grid handled badly and a tree must not get wrong: a sheet of 1 mm triangles, a few triangles
// hundreds of mm across cutting through it, copies of one triangle under other indices (exact ties), and a stack of
// parallel triangles 0.01 mm apart.
std::vector<Tri> awkward_mesh() {
  std::vector<Tri> mesh;
  std::uint32_t index = 0;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      const glm::vec3 o(static_cast<float>(i), static_cast<float>(j), 0.0f);
      mesh.push_back({o, o + glm::vec3(1, 0, 0), o + glm::vec3(1, 1, 0.2f), index++});
      mesh.push_back({o, o + glm::vec3(1, 1, 0.2f), o + glm::vec3(0, 1, 0), index++});
    }
  mesh.push_back({{-300, -300, 5}, {300, -300, -5}, {0, 400, 3}, index++});
  mesh.push_back({{15, -200, -200}, {15, 200, -200}, {15, 0, 300}, index++});
  for (int k = 0; k < 3; ++k) mesh.push_back({{5, 5, 1}, {7, 5, 1}, {5, 7, 1}, index++});
  for (int k = 0; k < 20; ++k) {
    const float z = 2.0f + 0.01f * static_cast<float>(k);
    mesh.push_back({{20, 20, z}, {24, 20, z}, {20, 24, z}, index++});
  }
  // Shuffle the indices' order in the list: the tie goes to the smaller index, not to the earlier entry.
  util::Rng rng(5);
  for (std::size_t i = mesh.size() - 1; i > 0; --i) std::swap(mesh[i], mesh[rng.below(i + 1)]);
  return mesh;
}

}  // namespace

TEST_CASE("triangle tree: the nearest triangle is the search of every triangle's, bit for bit") {
  const std::vector<Tri> mesh = awkward_mesh();
  const TriangleTree tree(mesh);
  REQUIRE(tree.size() == mesh.size());
  util::Rng rng(17);
  std::size_t found = 0, far = 0;
  for (int k = 0; k < 4000; ++k) {
    const glm::dvec3 p(40.0 * rng.uniform() - 5.0, 40.0 * rng.uniform() - 5.0, 8.0 * rng.uniform() - 4.0);
    const double radius = k % 4 == 0 ? 0.3 : (k % 4 == 1 ? 2.0 : (k % 4 == 2 ? 6.0 : 500.0));
    const TriangleTree::Hit want = every_triangle(mesh, p, radius);
    const TriangleTree::Hit got = tree.nearest(p, radius);
    INFO("query " << k << " at (" << p.x << ", " << p.y << ", " << p.z << "), radius " << radius);
    REQUIRE(got.found == want.found);
    if (!want.found) {
      ++far;
      continue;
    }
    ++found;
    CHECK(got.index == want.index);
    CHECK(got.d2 == want.d2);
    CHECK(got.point == want.point);
  }
  CHECK(found > 2000);  // both outcomes are exercised
  CHECK(far > 100);
}

TEST_CASE("triangle tree: exact ties go to the smaller index, and nothing lies at the radius or past it") {
  std::vector<Tri> mesh;
  for (std::uint32_t i : {7u, 3u, 9u}) mesh.push_back({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, i});
  const TriangleTree tree(mesh);
  const TriangleTree::Hit above = tree.nearest({0.5, 0.5, 1.0}, 2.0);
  REQUIRE(above.found);
  CHECK(above.index == 3);
  CHECK(above.d2 == 1.0);
  CHECK_FALSE(tree.nearest({0.5, 0.5, 1.0}, 1.0).found);  // strictly within: at exactly 1 mm it is not
  CHECK_FALSE(tree.nearest({0.5, 0.5, 1.0}, 0.0).found);
  CHECK_FALSE(TriangleTree().nearest({0, 0, 0}, 10.0).found);
}

TEST_CASE("triangle tree: far from the origin, where Embree's float query rounds by hundredths of a mm, bit for bit") {
  // The awkward mesh moved a quarter of a kilometre: a float coordinate there is a multiple of 1/64 mm, so the query
  // Embree sees lies up to 0.008 mm off each axis, more than the gaps of the stacked triangles.
  const glm::vec3 offset(1.0e5f, -2.5e5f, 4.0e4f);
  std::vector<Tri> mesh = awkward_mesh();
  for (Tri& t : mesh) t.a += offset, t.b += offset, t.c += offset;
  const TriangleTree tree(mesh);
  util::Rng rng(23);
  std::size_t found = 0;
  for (int k = 0; k < 3000; ++k) {
    const glm::dvec3 p = glm::dvec3(offset) +
                         glm::dvec3(40.0 * rng.uniform() - 5.0, 40.0 * rng.uniform() - 5.0, 8.0 * rng.uniform() - 4.0);
    const double radius = k % 3 == 0 ? 0.05 : (k % 3 == 1 ? 1.0 : 6.0);
    const TriangleTree::Hit want = every_triangle(mesh, p, radius);
    const TriangleTree::Hit got = tree.nearest(p, radius);
    INFO("query " << k << ", radius " << radius);
    REQUIRE(got.found == want.found);
    if (!want.found) continue;
    ++found;
    CHECK(got.index == want.index);
    CHECK(got.d2 == want.d2);
  }
  CHECK(found > 1000);
}

TEST_CASE("triangle tree: many threads at once find what one thread finds") {
  const std::vector<Tri> mesh = awkward_mesh();
  const TriangleTree tree(mesh);
  std::vector<glm::dvec3> points;
  util::Rng rng(29);
  for (int k = 0; k < 2000; ++k)
    points.emplace_back(40.0 * rng.uniform() - 5.0, 40.0 * rng.uniform() - 5.0, 8.0 * rng.uniform() - 4.0);
  std::vector<std::uint64_t> want;
  for (const glm::dvec3& p : points) {
    const TriangleTree::Hit h = tree.nearest(p, 3.0);
    want.push_back(h.found ? h.index : ~0ull);
  }
  std::vector<std::vector<std::uint64_t>> got(8);
  std::vector<std::thread> workers;
  for (std::size_t w = 0; w < got.size(); ++w)
    workers.emplace_back([&, w] {
      for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::dvec3& p = points[(i + 250 * w) % points.size()];  // each thread its own order
        const TriangleTree::Hit h = tree.nearest(p, 3.0);
        got[w].push_back(h.found ? h.index : ~0ull);
      }
    });
  for (std::thread& t : workers) t.join();
  for (std::size_t w = 0; w < got.size(); ++w)
    for (std::size_t i = 0; i < points.size(); ++i) REQUIRE(got[w][i] == want[(i + 250 * w) % points.size()]);
}

TEST_CASE("triangle tree: moved, it searches as before, and points it cannot search find nothing") {
  std::vector<Tri> mesh{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, 4u}};
  TriangleTree tree(mesh);
  TriangleTree moved(std::move(tree));
  REQUIRE(moved.nearest({0.5, 0.5, 1.0}, 2.0).found);
  TriangleTree assigned;
  assigned = std::move(moved);
  CHECK(assigned.nearest({0.5, 0.5, 1.0}, 2.0).index == 4u);
  CHECK(assigned.nearest({0.5, 0.5, 1.0}, std::numeric_limits<double>::infinity()).found);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(assigned.nearest({nan, 0.5, 1.0}, 2.0).found);
  CHECK_FALSE(assigned.nearest({1e31, 0.5, 1.0}, 2.0).found);
  CHECK_FALSE(assigned.nearest({0.5, 0.5, 1.0}, nan).found);
}
