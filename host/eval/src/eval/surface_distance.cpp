#include "eval/surface_distance.hpp"

#include <sva/base/closest_point.hpp>
#include <sva/base/finite.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
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
  glm::dvec3 lo(1e300), hi(-1e300), first_moment(0.0);
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
    if (!(area > 0.0)) continue;  // degenerate: no surface, and it would only slow the grid
    triangles_.push_back(tri);
    total_area_ += area;
    cumulative_area_.push_back(total_area_);
    const glm::dvec3 sum = tri.a + tri.b + tri.c;
    first_moment += sum * (area / 3.0);
    // Integral of x x^T over a triangle: A / 12 (sum_i v_i v_i^T + s s^T), s = sum_i v_i.
    second += (glm::outerProduct(tri.a, tri.a) + glm::outerProduct(tri.b, tri.b) + glm::outerProduct(tri.c, tri.c) +
               glm::outerProduct(sum, sum)) *
              (area / 12.0);
    lo = glm::min(lo, glm::min(tri.a, glm::min(tri.b, tri.c)));
    hi = glm::max(hi, glm::max(tri.a, glm::max(tri.b, tri.c)));
  }
  if (!(total_area_ > 0.0) || !std::isfinite(total_area_))
    throw Error(what + ": the mesh has no triangle of positive area");
  centroid_ = first_moment / total_area_;
  scatter_ = second - glm::outerProduct(centroid_, centroid_) * total_area_;
  diameter_ = diameter_of(vertices_);
  build_grid(lo, hi);
}

void SurfaceDistance::build_grid(const glm::dvec3& lo, const glm::dvec3& hi) {
  // A surface of n cells along its longest side crosses some 6 n^2 cells: n = sqrt(triangles / 12) puts about two
  // triangles in each (a query then tests tens of triangles, not hundreds).
  const glm::dvec3 extent = hi - lo;
  const double per_side = std::clamp(std::sqrt(static_cast<double>(triangles_.size()) / 12.0), 8.0, 160.0);
  cell_ = std::max({extent.x, extent.y, extent.z, 1e-9}) / per_side;
  origin_ = lo;
  for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / cell_)));
  const auto cell_of = [&](const glm::dvec3& p) {
    glm::ivec3 c;
    for (int k = 0; k < 3; ++k)
      c[k] = std::clamp(static_cast<int>(std::floor((p[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
    return c;
  };
  const std::size_t cells = static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z;
  // Two passes over the triangles' cells (count, then place): one flat list, triangles in index order per cell.
  const auto for_each_cell = [&](const Triangle& t, auto&& visit) {
    const glm::ivec3 a = cell_of(glm::min(t.a, glm::min(t.b, t.c))), b = cell_of(glm::max(t.a, glm::max(t.b, t.c)));
    for (int z = a.z; z <= b.z; ++z)
      for (int y = a.y; y <= b.y; ++y)
        for (int x = a.x; x <= b.x; ++x) visit((static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x);
  };
  cell_start_.assign(cells + 1, 0);
  for (const Triangle& t : triangles_) for_each_cell(t, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_items_.resize(cell_start_[cells]);
  std::vector<std::uint32_t> next(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i)
    for_each_cell(triangles_[i], [&](std::size_t c) { cell_items_[next[c]++] = static_cast<std::uint32_t>(i); });
  find_empty_rings();
}

void SurfaceDistance::find_empty_rings() {
  // Breadth first from every cell that holds a triangle over the 26 neighbours: the number of steps is the
  // Chebyshev distance in cells, the shells a query may skip.
  const std::size_t cells = cell_start_.size() - 1;
  empty_rings_.assign(cells, std::numeric_limits<std::uint32_t>::max());
  std::vector<std::size_t> frontier;
  for (std::size_t c = 0; c < cells; ++c)
    if (cell_start_[c + 1] > cell_start_[c]) {
      empty_rings_[c] = 0;
      frontier.push_back(c);
    }
  for (std::uint32_t ring = 1; !frontier.empty(); ++ring) {
    std::vector<std::size_t> next;
    for (const std::size_t c : frontier) {
      const int x = static_cast<int>(c % static_cast<std::size_t>(dims_.x));
      const int y = static_cast<int>((c / static_cast<std::size_t>(dims_.x)) % static_cast<std::size_t>(dims_.y));
      const int z = static_cast<int>(c / (static_cast<std::size_t>(dims_.x) * static_cast<std::size_t>(dims_.y)));
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy, nz = z + dz;
            if (nx < 0 || ny < 0 || nz < 0 || nx >= dims_.x || ny >= dims_.y || nz >= dims_.z) continue;
            const std::size_t n = (static_cast<std::size_t>(nz) * dims_.y + ny) * dims_.x + nx;
            if (empty_rings_[n] > ring) {
              empty_rings_[n] = ring;
              next.push_back(n);
            }
          }
    }
    frontier = std::move(next);
  }
}

double SurfaceDistance::nearest_in_cell(std::size_t cell, const glm::dvec3& p, double best) const {
  for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const Triangle& t = triangles_[cell_items_[k]];
    best = std::min(best, length2(p - closest_on_triangle(p, t.a, t.b, t.c)));
  }
  return best;
}

double SurfaceDistance::distance(const glm::dvec3& p, double cap) const {
  // Shells of cells around the cell nearest to p, nearer first. After shell s every triangle in the block of cells
  // within s of it has been seen; any other one lies outside the block, at least as far from p's projection q onto
  // the grid's box as q is from the block's faces (the projection onto a convex set brings no point of it nearer).
  glm::ivec3 c;
  glm::dvec3 q;
  for (int k = 0; k < 3; ++k) {
    c[k] = std::clamp(static_cast<int>(std::floor((p[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
    q[k] = std::clamp(p[k], origin_[k], origin_[k] + dims_[k] * cell_);
  }
  const int max_shell = std::max({dims_.x, dims_.y, dims_.z});
  double best = 1e300;  // squared
  // The shells nearer than the nearest cell with a triangle are empty: start at it.
  const std::size_t home = (static_cast<std::size_t>(c.z) * dims_.y + c.y) * dims_.x + c.x;
  for (int s = static_cast<int>(std::min<std::uint32_t>(empty_rings_[home], static_cast<std::uint32_t>(max_shell)));
       s <= max_shell; ++s) {
    for (int z = c.z - s; z <= c.z + s; ++z) {
      if (z < 0 || z >= dims_.z) continue;
      for (int y = c.y - s; y <= c.y + s; ++y) {
        if (y < 0 || y >= dims_.y) continue;
        const bool face = std::abs(z - c.z) == s || std::abs(y - c.y) == s;
        for (int x = c.x - s; x <= c.x + s; x += (face || s == 0) ? 1 : 2 * s) {
          if (x < 0 || x >= dims_.x) continue;
          // A cell whose box lies no nearer than the best so far holds no nearer triangle.
          const glm::ivec3 cell(x, y, z);
          double box = 0.0;
          for (int k = 0; k < 3; ++k) {
            const double lo = origin_[k] + cell[k] * cell_, gap = std::max({lo - p[k], p[k] - (lo + cell_), 0.0});
            box += gap * gap;
          }
          if (box < best) best = nearest_in_cell((static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x, p, best);
        }
      }
    }
    double reach = 1e300;
    for (int k = 0; k < 3; ++k) {
      // A face of the block on the grid's boundary has nothing beyond it.
      if (c[k] - s > 0) reach = std::min(reach, q[k] - (origin_[k] + (c[k] - s) * cell_));
      if (c[k] + s + 1 < dims_[k]) reach = std::min(reach, origin_[k] + (c[k] + s + 1) * cell_ - q[k]);
    }
    if (best <= reach * reach || reach >= cap) break;
  }
  return std::sqrt(best);
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
