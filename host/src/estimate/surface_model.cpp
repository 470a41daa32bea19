#include "estimate/surface_model.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace sva {

namespace {

// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection 5.1.5): by the Voronoi region
// of p, each case in a fixed order of double operations, so every machine finds the same point.
glm::dvec3 closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Grid coordinates are kept within +-2^20 per axis: 21 bits each in a cell's key.
constexpr int kCellLimit = 1 << 20;
// A triangle's bounding box in cells: a 400 mm face of a letter at 0.5 mm cells is 640,000; more is a mesh that does
// not fit its pose space, refused rather than filling memory.
constexpr double kMaxCellsPerTriangle = 1 << 22;

}  // namespace

std::uint64_t SurfaceModel::cell_key(const glm::ivec3& c) const {
  auto u = [](int v) { return static_cast<std::uint64_t>(v + kCellLimit) & 0x1fffffu; };
  return u(c.x) | (u(c.y) << 21) | (u(c.z) << 42);
}

glm::ivec3 SurfaceModel::cell_of(const Mesh& m, const glm::dvec3& p) const {
  glm::ivec3 c;
  for (int k = 0; k < 3; ++k) {
    const double v = std::floor((p[k] - m.origin[k]) / cell_);
    c[k] = static_cast<int>(std::clamp(v, -double(kCellLimit - 2), double(kCellLimit - 2)));
  }
  return c;
}

SurfaceModel::SurfaceModel(const std::vector<ObjectSurface>& surfaces, double cell_mm) : cell_(cell_mm) {
  if (!(cell_mm > 0.0) || !std::isfinite(cell_mm)) throw Error("surface model: the cell size must be positive");
  meshes_.resize(surfaces.size());
  for (std::size_t o = 0; o < surfaces.size(); ++o) {
    const ObjectSurface& s = surfaces[o];
    Mesh& m = meshes_[o];
    if (s.positions.empty()) continue;
    m.origin = glm::dvec3(s.positions.front());
    for (const glm::vec3& v : s.positions) m.origin = glm::min(m.origin, glm::dvec3(v));
    for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
      const glm::uvec3 tri = s.triangles[t];
      const glm::dvec3 a(s.positions[tri.x]), b(s.positions[tri.y]), c(s.positions[tri.z]);
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double len = glm::length(n);
      if (!(len > 0.0)) continue;  // a degenerate triangle has no side to touch
      const std::uint32_t kept = static_cast<std::uint32_t>(m.a.size());
      m.a.push_back(a), m.b.push_back(b), m.c.push_back(c), m.normal.push_back(n / len), m.index.push_back(t);
      const glm::ivec3 lo = cell_of(m, glm::min(a, glm::min(b, c))), hi = cell_of(m, glm::max(a, glm::max(b, c)));
      const glm::dvec3 span = glm::dvec3(hi - lo) + 1.0;
      if (span.x * span.y * span.z > kMaxCellsPerTriangle)
        throw Error("surface model: triangle " + std::to_string(t) + " of object " + std::to_string(o) +
                    " spans more than " + std::to_string(static_cast<long>(kMaxCellsPerTriangle)) + " cells of " +
                    std::to_string(cell_mm) + " mm (a mesh far larger than its object's pose space?)");
      for (int x = lo.x; x <= hi.x; ++x)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int z = lo.z; z <= hi.z; ++z) m.cells[cell_key({x, y, z})].push_back(kept);
    }
  }
}

SurfaceModel::Nearest SurfaceModel::nearest(std::uint32_t object, const glm::dvec3& p, double radius) const {
  Nearest best;
  if (object >= meshes_.size()) return best;
  const Mesh& m = meshes_[object];
  if (m.a.empty()) return best;
  radius = std::min(radius, cell_);
  const glm::ivec3 lo = cell_of(m, p - glm::dvec3(radius)), hi = cell_of(m, p + glm::dvec3(radius));
  double best_d2 = radius * radius;
  std::uint32_t best_kept = 0;
  for (int x = lo.x; x <= hi.x; ++x)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int z = lo.z; z <= hi.z; ++z) {
        const auto it = m.cells.find(cell_key({x, y, z}));
        if (it == m.cells.end()) continue;
        for (std::uint32_t t : it->second) {
          const glm::dvec3 q = closest_on_triangle(p, m.a[t], m.b[t], m.c[t]);
          const double d2 = glm::dot(q - p, q - p);
          if (d2 < best_d2 || (d2 == best_d2 && best.found && t < best_kept)) {
            best_d2 = d2, best_kept = t, best.found = true, best.point = q;
          }
        }
      }
  if (!best.found) return best;
  best.normal = m.normal[best_kept];
  best.distance = std::sqrt(best_d2);
  best.triangle = m.index[best_kept];
  return best;
}

double SurfaceModel::log2_likelihood(std::uint32_t object, const ObservedReading& r, const RigidPose& pose,
                                     const ContactNoise& noise) const {
  // The reading in the object's frame: the hypothesis says where the object is.
  const glm::dvec3 p = glm::transpose(pose.R) * (r.position - pose.T);
  const glm::dvec3 n = glm::transpose(pose.R) * r.normal;
  const Nearest q = nearest(object, p, noise.reach_mm);
  if (!q.found) return pmath::log2(noise.floor);
  const glm::dvec3 tilt = n - q.normal;
  const double s2 = q.distance * q.distance + noise.normal_weight_mm * noise.normal_weight_mm * glm::dot(tilt, tilt);
  return pmath::log2(pmath::exp(-0.5 * s2 / (noise.sigma_mm * noise.sigma_mm)) + noise.floor);
}

double SurfaceModel::log2_likelihood(std::uint32_t object, std::span<const ObservedReading> readings,
                                     const RigidPose& pose, const ContactNoise& noise) const {
  double bits = 0.0;
  for (const ObservedReading& r : readings) bits += log2_likelihood(object, r, pose, noise);
  return bits;
}

}  // namespace sva
