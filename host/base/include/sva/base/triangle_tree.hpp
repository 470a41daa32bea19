#pragma once
// The triangle of a mesh nearest to a point, the one home of the search (the verify stage's measurement model, the
// fine pose on the mesh, the touch planner). A bounding-volume tree: boxes halved at the median of their triangles'
// centres down to a few triangles a leaf, searched nearest box first, passing over every box wholly farther than the
// best triangle so far. Its answer is the smallest (squared distance, index) of all triangles within the radius,
// each distance from closest_on_triangle in double: it does not depend on the order of the visits, so the tree's
// shape (and the standard library's partition) changes the time, never the bits. Its memory is linear in the
// triangles, whatever their size: a letter's 400 mm face is one entry, as a sub-millimetre facet of a scanned mug is.
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace sva {

class TriangleTree {
 public:
  // A mesh's triangle as sva stores meshes (ObjectSurface: float corners), and what the search returns for it:
  // `index`, which also orders ties (the smaller first).
  struct Triangle {
    glm::vec3 a, b, c;
    std::uint32_t index;
  };
  TriangleTree() = default;
  // Corners finite (the caller checks).
  explicit TriangleTree(std::vector<Triangle> triangles);

  struct Hit {
    bool found = false;
    std::uint32_t index = 0;  // the triangle's Triangle::index
    glm::dvec3 point{0.0};    // closest_on_triangle(p, its corners)
    double d2 = 0.0;          // |point - p|^2
  };
  // The triangle with the smallest (squared distance, index) among those strictly within `radius` of p.
  Hit nearest(const glm::dvec3& p, double radius) const;

  std::size_t size() const { return triangles_.size(); }

 private:
  // A box and what it holds: a leaf's triangles are triangles_[first, first + count); an inner node's (count 0)
  // children are the pair pairs_[first]. Bounds are the corners' own floats, so a box holds its triangles exactly.
  struct Node {
    float lo[3];
    std::uint32_t first;
    float hi[3];
    std::uint32_t count;
  };
  // Two siblings in one cache line: a visit reads both children's boxes at once.
  struct alignas(64) Pair {
    Node child[2];
  };
  Node build(std::span<Triangle> triangles, std::uint32_t begin);

  Node root_{};
  std::vector<Pair> pairs_;
  std::vector<Triangle> triangles_;  // in the leaves' order
};

}  // namespace sva
