#include "eval/surface_distance.hpp"

#include <sva/base/finite.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace sva::eval {

namespace {

double dot(const glm::dvec3& a, const glm::dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double length2(const glm::dvec3& a) { return dot(a, a); }

// The largest distance between two of `points`. Its ends are extreme points of the set: they are sought among the
// farthest points along 400 directions spread over the sphere (a Fibonacci lattice), which keeps a mesh of many
// vertices from costing seconds. The lattice's directions lie within about 6 degrees of any direction, so the
// width along the nearest one, and with it the answer, is at least cos(6 deg) = 99.4% of the diameter.
double diameter_of(const std::vector<glm::dvec3>& points) {
  std::vector<std::size_t> order;
  constexpr int kDirections = 400;
  for (int k = 0; k < kDirections; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / kDirections, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    double s = 0.0, c = 0.0;
    pmath::sincos(2.399963229728653 * k, s, c);  // the golden angle
    const glm::dvec3 d(r * c, r * s, z);
    std::size_t best_i = 0;
    double best_along = dot(points[0], d);
    for (std::size_t i = 1; i < points.size(); ++i)
      if (const double along = dot(points[i], d); along > best_along) {
        best_along = along;
        best_i = i;
      }
    order.push_back(best_i);
  }
  std::sort(order.begin(), order.end());
  order.erase(std::unique(order.begin(), order.end()), order.end());
  double best = 0.0;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (std::size_t j = i + 1; j < order.size(); ++j)
      best = std::max(best, length2(points[order[i]] - points[order[j]]));
  return std::sqrt(best);
}

}  // namespace

SurfaceDistance::SurfaceDistance(const ObjectSurface& surface, const std::string& what) {
  glm::dvec3 first_moment(0.0);
  std::vector<TriangleTree::Triangle> searched;
  glm::dmat3 second(0.0);
  for (const glm::vec3& v : surface.positions) {
    const glm::dvec3 p(v);
    if (!finite(p)) throw Error(what + ": a vertex position is not finite");
    vertices_.push_back(p);
  }
  for (const glm::uvec3& t : surface.triangles) {
    if (t.x >= vertices_.size() || t.y >= vertices_.size() || t.z >= vertices_.size())
      throw Error(what + ": a triangle index is out of range (" + std::to_string(vertices_.size()) + " vertices)");
    const Triangle tri{vertices_[t.x], vertices_[t.y], vertices_[t.z]};
    const double area = 0.5 * std::sqrt(length2(glm::cross(tri.b - tri.a, tri.c - tri.a)));
    if (!(area > 0.0)) continue;  // degenerate: no surface, and it would only slow the search
    searched.push_back({surface.positions[t.x], surface.positions[t.y], surface.positions[t.z],
                        static_cast<std::uint32_t>(triangles_.size())});
    triangles_.push_back(tri);
    total_area_ += area;
    cumulative_area_.push_back(total_area_);
    const glm::dvec3 sum = tri.a + tri.b + tri.c;
    first_moment += sum * (area / 3.0);
    // Integral of x x^T over a triangle: A / 12 (sum_i v_i v_i^T + s s^T), s = sum_i v_i.
    second += (glm::outerProduct(tri.a, tri.a) + glm::outerProduct(tri.b, tri.b) + glm::outerProduct(tri.c, tri.c) +
               glm::outerProduct(sum, sum)) *
              (area / 12.0);
  }
  if (!(total_area_ > 0.0) || !std::isfinite(total_area_))
    throw Error(what + ": the mesh has no triangle of positive area");
  centroid_ = first_moment / total_area_;
  scatter_ = second - glm::outerProduct(centroid_, centroid_) * total_area_;
  diameter_ = diameter_of(vertices_);
  tree_ = TriangleTree(std::move(searched));
}

double SurfaceDistance::distance(const glm::dvec3& p, double cap) const {
  const TriangleTree::Hit hit = tree_.nearest(p, cap);
  return hit.found ? std::sqrt(hit.d2) : cap;
}

std::vector<glm::dvec3> SurfaceDistance::sample(std::size_t count, std::uint64_t seed) const {
  util::Rng rng(seed, 0x5ea5u);
  std::vector<glm::dvec3> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double u = rng.uniform() * total_area_;
    const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), u);
    const Triangle& t = triangles_[std::min<std::size_t>(static_cast<std::size_t>(it - cumulative_area_.begin()),
                                                         triangles_.size() - 1)];
    // Uniform on the triangle: the square root folds the unit square onto it without bias.
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    out.push_back(t.a * (1.0 - r1) + t.b * (r1 * (1.0 - r2)) + t.c * (r1 * r2));
  }
  return out;
}

}  // namespace sva::eval
