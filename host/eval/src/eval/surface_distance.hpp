#pragma once
// An object's mesh as the pose errors measure it (docs/pose-errors.md): the
// distance from any point to the nearest point of the surface, and points
// sampled evenly over it. Both are computed by our own code in a fixed order
// from +, -, *, / and sqrt (the distance through sva/base/triangle_tree.hpp), so
// the answers are the same bits on every CPU and for any thread count (DESIGN 4:
// Embree's point queries walk a BVH built by kernels chosen per CPU).
#include <sva/base/triangle_tree.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/map.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace sva::eval {

class SurfaceDistance {
 public:
  // Throws sva::Error naming `what` when the surface has no triangle of positive area, an index out of range or a
  // non-finite position.
  SurfaceDistance(const ObjectSurface& surface, const std::string& what);

  // The distance from `p` to the surface; when it is at least `cap`, some value >= cap (the search stops there).
  double distance(const glm::dvec3& p, double cap = 1e300) const;

  // `count` points on the surface, each triangle drawn with probability proportional to its area and the point
  // uniform on it, from util::Rng(seed): the same points on every machine.
  std::vector<glm::dvec3> sample(std::size_t count, std::uint64_t seed) const;

  double area() const { return total_area_; }
  glm::dvec3 centroid() const { return centroid_; }  // of the surface (area-weighted)
  // The surface's second moment about its centroid, integral of (x - c)(x - c)^T dA (exact per triangle).
  const glm::dmat3& scatter() const { return scatter_; }
  // The largest distance between two vertices (BOP's model diameter).
  double diameter() const { return diameter_; }
  const std::vector<glm::dvec3>& vertices() const { return vertices_; }

 private:
  struct Triangle {
    glm::dvec3 a, b, c;
  };
  std::vector<glm::dvec3> vertices_;
  std::vector<Triangle> triangles_;  // those of positive area
  std::vector<double> cumulative_area_;
  double total_area_ = 0.0, diameter_ = 0.0;
  glm::dvec3 centroid_{0.0};
  glm::dmat3 scatter_{0.0};
  TriangleTree tree_;  // the triangles_ of positive area, numbered as there
};

// find_symmetries on a surface already built (`mesh` is `surface`'s): the evaluation keeps it for ADD-S.
MeshSymmetry find_symmetries(const ObjectSurface& surface, const SurfaceDistance& mesh, const SymmetrySearch& search);

}  // namespace sva::eval
