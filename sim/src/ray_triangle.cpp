#include "ray_triangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace sva::sim {

TriangleTest intersect_triangle(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                                const glm::dvec3& c) {
  // Shear the ray onto +z: kz is the direction's largest axis, the others
  // follow in a right-handed order (swapped for a negative kz keeps the winding).
  TriangleTest r;
  const glm::dvec3 ad = glm::abs(d);
  const int kz = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (d[kz] < 0) std::swap(kx, ky);
  if (d[kz] == 0) return r;  // a zero direction
  const double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  const glm::dvec3 A = a - o, B = b - o, C = c - o;
  const double ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
  const double bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
  const double cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
  // Scaled barycentrics: an edge's value depends on its two vertices only, so
  // both triangles of a shared edge see it with one sign (watertight).
  const double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
  const double size = std::fabs(u) + std::fabs(v) + std::fabs(w);
  r.near_edge = !(std::min({std::fabs(u), std::fabs(v), std::fabs(w)}) > 1e-3 * size);
  if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return r;
  const double det = u + v + w;
  if (det == 0) return r;
  const double t = (u * (sz * A[kz]) + v * (sz * B[kz]) + w * (sz * C[kz])) / det;
  if (!std::isfinite(t)) return r;
  r.hit = true;
  r.t = t;
  return r;
}

glm::dvec3 triangle_normal(const Mesh& mesh, std::uint32_t triangle) {
  const glm::uvec3& t = mesh.triangles[triangle];
  const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = std::sqrt(glm::dot(n, n));
  return len > 0 ? n / len : glm::dvec3(0.0);
}

TriangleRings::TriangleRings(const Mesh& mesh) {
  // Weld: one id per distinct position (exact float coordinates).
  std::map<std::array<float, 3>, std::uint32_t> ids;
  std::vector<std::uint32_t> welded(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    welded[i] = ids.emplace(std::array<float, 3>{p.x, p.y, p.z}, static_cast<std::uint32_t>(ids.size())).first->second;
  }
  corner_.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) corner_.push_back(welded[t[k]]);
  // Counting sort of the triangles by corner.
  start_.assign(ids.size() + 1, 0);
  for (std::uint32_t v : corner_) ++start_[v + 1];
  for (std::size_t v = 0; v < ids.size(); ++v) start_[v + 1] += start_[v];
  ring_.resize(corner_.size());
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < corner_.size(); ++i) ring_[fill[corner_[i]]++] = static_cast<std::uint32_t>(i / 3);
}

void TriangleRings::expand(std::vector<std::uint32_t>& triangles) const {
  const std::size_t n = triangles.size();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = corner_[3 * std::size_t{triangles[i]} + k];
      triangles.insert(triangles.end(), ring_.begin() + start_[v], ring_.begin() + start_[v + 1]);
    }
  std::sort(triangles.begin(), triangles.end());
  triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
}

}  // namespace sva::sim
