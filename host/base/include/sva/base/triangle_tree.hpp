#pragma once
// The triangle of a mesh nearest to a point, the one home of the search (the verify stage's measurement model, the
// fine pose on the mesh, the touch planner, the pose errors). Embree's bounding-volume hierarchy finds the
// triangles whose boxes reach within the best distance so far (rtcPointQuery); each is weighed by
// closest_on_triangle in double. The answer is the smallest (squared distance, index) of all triangles within the
// radius: it does not depend on the order of the visits, nor on Embree's tree, its ISA or its threads, since every
// box Embree passes over lies farther than the best triangle by a margin above the rounding of its float query.
#include <sva/base/embree.hpp>

#include <glm/glm.hpp>

#include <cstdint>
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

  TriangleTree();
  // Corners finite (the caller checks). Throws sva::Error when Embree cannot build the tree (out of memory).
  explicit TriangleTree(const std::vector<Triangle>& triangles);
  ~TriangleTree();
  TriangleTree(TriangleTree&&) noexcept;
  TriangleTree& operator=(TriangleTree&&) noexcept;

  struct Hit {
    bool found = false;
    std::uint32_t index = 0;  // the triangle's Triangle::index
    glm::dvec3 point{0.0};    // closest_on_triangle(p, its corners)
    double d2 = 0.0;          // |point - p|^2
  };
  // The triangle with the smallest (squared distance, index) among those strictly within `radius` of p; none for a
  // point that is not finite or lies past 1e30 mm (Embree's query is in floats). Safe from many threads at once.
  Hit nearest(const glm::dvec3& p, double radius) const;

  std::size_t size() const { return index_.size(); }

 private:
  std::vector<float> corners_;        // 9 a triangle (a, b, c): Embree's vertex buffer, shared, and the search's
  std::vector<std::uint32_t> index_;  // each triangle's Triangle::index
  embree::Scene scene_;
};

}  // namespace sva
