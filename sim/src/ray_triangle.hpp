#pragma once
// The simulator's exact ray-triangle hit (object_geometry.cpp asks Embree for
// candidates only): the watertight test of Woop, Benthin and Wald (JCGT 2013)
// in double precision, and the triangles that share a corner position, so that
// a candidate's neighbours are tested too. Only +, -, *, / and sqrt, so the
// same inputs give the same bits on every x86-64 CPU.
#include <sva/sim/mesh.hpp>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace sva::sim {

// The test of o + t d against triangle (a, b, c), either side facing. A ray
// through a shared edge or vertex hits at least one of the triangles there.
// `near_edge`: the ray passes within a relative 1e-3 of the triangle's boundary
// (hit or miss), where Embree's single-precision kernels may decide otherwise
// than this test, so the triangles around it must be tested too. The band is
// about 1e-3 mm on a 1 mm triangle, a hundred times the rounding of a float
// coordinate near 80 mm (5e-6 mm), the simulator's object-frame scale.
struct TriangleTest {
  bool hit = false;
  double t = 0.0;
  bool near_edge = false;
};
TriangleTest intersect_triangle(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                                const glm::dvec3& c);

// The unit geometric normal (v1 - v0) x (v2 - v0) of a triangle, Embree's convention.
glm::dvec3 triangle_normal(const Mesh& mesh, std::uint32_t triangle);

// For each vertex position (vertices welded by exact coordinates, since glTF
// meshes often repeat a vertex per face), the triangles that touch it.
class TriangleRings {
 public:
  TriangleRings() = default;
  explicit TriangleRings(const Mesh& mesh);
  // Adds to `triangles` every triangle sharing a corner with one of them; sorted, without repeats.
  void expand(std::vector<std::uint32_t>& triangles) const;

 private:
  std::vector<std::uint32_t> corner_;  // 3 welded vertex ids per triangle
  std::vector<std::uint32_t> start_;   // per welded vertex: its run in ring_
  std::vector<std::uint32_t> ring_;    // triangles, grouped by welded vertex
};

}  // namespace sva::sim
