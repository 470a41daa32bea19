#include "estimate/surface_model.hpp"

#include <sva/base/closest_point.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace sva {

namespace {

// Grid coordinates are kept within +-2^20 per axis: 21 bits each in a cell's key.
constexpr int kCellLimit = 1 << 20;
// A triangle's bounding box in cells: a 400 mm face of a letter at 0.5 mm cells is 640,000; more is a mesh that does
// not fit its pose space, refused rather than filling memory.
constexpr double kMaxCellsPerTriangle = 1 << 22;

}  // namespace

// A triangle's bounding sphere in floats: its corners' mean and the farthest corner's distance, widened by more than
// the centre's rounding to float (6e-8 of its coordinates) and the bound's own, so that the sphere still holds every
// point of the triangle. Floats halve what a query reads.
SurfaceModel::CellEntry SurfaceModel::bounding_sphere(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 centre = (a + b + c) / 3.0;
  const double far = std::max({glm::length(a - centre), glm::length(b - centre), glm::length(c - centre)});
  const double largest = std::max({std::fabs(centre.x), std::fabs(centre.y), std::fabs(centre.z)});
  const double widened = far * (1.0 + 1e-6) + 1e-6 * largest + 1e-6;
  return {static_cast<float>(centre.x), static_cast<float>(centre.y), static_cast<float>(centre.z),
          std::nextafter(static_cast<float>(widened), std::numeric_limits<float>::infinity())};
}

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
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> filed;  // each cell's kept triangles, in order
    for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
      const glm::uvec3 tri = s.triangles[t];
      const glm::dvec3 a(s.positions[tri.x]), b(s.positions[tri.y]), c(s.positions[tri.z]);
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double len = glm::length(n);
      if (!(len > 0.0)) continue;  // a degenerate triangle has no side to touch
      const std::uint32_t kept = static_cast<std::uint32_t>(m.a.size());
      m.a.push_back(a), m.b.push_back(b), m.c.push_back(c), m.normal.push_back(n / len), m.index.push_back(t);
      m.sphere.push_back(bounding_sphere(a, b, c));
      const glm::ivec3 lo = cell_of(m, glm::min(a, glm::min(b, c))), hi = cell_of(m, glm::max(a, glm::max(b, c)));
      const glm::dvec3 span = glm::dvec3(hi - lo) + 1.0;
      if (span.x * span.y * span.z > kMaxCellsPerTriangle)
        throw Error("surface model: triangle " + std::to_string(t) + " of object " + std::to_string(o) +
                    " spans more than " + std::to_string(static_cast<long>(kMaxCellsPerTriangle)) + " cells of " +
                    std::to_string(cell_mm) + " mm (a mesh far larger than its object's pose space?)");
      for (int x = lo.x; x <= hi.x; ++x)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int z = lo.z; z <= hi.z; ++z) filed[cell_key({x, y, z})].push_back(kept);
    }
    file_cells(filed, &m);
  }
}

// Every cell's triangles in one array, the cells' ranges of it by key: one allocation, where a list per cell was one
// each.
void SurfaceModel::file_cells(const std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>& filed, Mesh* m) {
  std::vector<std::uint64_t> keys;
  keys.reserve(filed.size());
  std::size_t entries = 0;
  for (const auto& [key, list] : filed) keys.push_back(key), entries += list.size();
  std::sort(keys.begin(), keys.end());
  m->filed.reserve(entries);
  m->cells.reserve(keys.size());
  for (std::uint64_t key : keys) {
    const std::vector<std::uint32_t>& list = filed.at(key);
    const std::size_t begin = m->filed.size();
    m->filed.insert(m->filed.end(), list.begin(), list.end());
    m->cells.emplace(key, std::make_pair(begin, m->filed.size()));
  }
}

namespace {

// A cell of the search and its distance from the query: the cells nearest first, so that the best triangle is found
// early and the cells wholly farther than it are passed over.
struct CellVisit {
  double d2;
  std::uint64_t key;
};

// The squared distance from p to the box [lo, lo + size] on every axis.
double box_distance2(const glm::dvec3& p, const glm::dvec3& lo, double size) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = lo[k] - p[k], above = p[k] - (lo[k] + size);
    const double d = std::max({below, above, 0.0});
    d2 += d * d;
  }
  return d2;
}

}  // namespace

// The triangle of filed[range.first, range.second) whose sphere's centre lies nearest to p (the first such).
std::uint32_t SurfaceModel::nearest_sphere(const Mesh& m, std::pair<std::size_t, std::size_t> range,
                                           const glm::dvec3& p) {
  std::uint32_t best = m.filed[range.first];
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t e = range.first; e < range.second; ++e) {
    const CellEntry& s = m.sphere[m.filed[e]];
    const glm::dvec3 d = p - glm::dvec3(s.x, s.y, s.z);
    const double d2 = glm::dot(d, d);
    if (d2 < best_d2) best_d2 = d2, best = m.filed[e];
  }
  return best;
}

SurfaceModel::Nearest SurfaceModel::nearest(std::uint32_t object, const glm::dvec3& p, double radius) const {
  Nearest best;
  if (object >= meshes_.size()) return best;
  const Mesh& m = meshes_[object];
  if (m.a.empty()) return best;
  radius = std::min(radius, cell_);
  const glm::ivec3 lo = cell_of(m, p - glm::dvec3(radius)), hi = cell_of(m, p + glm::dvec3(radius));
  // At most 3 cells an axis: the radius is at most a cell.
  std::array<CellVisit, 27> cells;
  std::size_t count = 0;
  for (int x = lo.x; x <= hi.x; ++x)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int z = lo.z; z <= hi.z; ++z) {
        const glm::dvec3 corner = m.origin + glm::dvec3(x, y, z) * cell_;
        cells[count++] = {box_distance2(p, corner, cell_), cell_key({x, y, z})};
      }
  std::sort(cells.begin(), cells.begin() + count,
            [](const CellVisit& u, const CellVisit& v) { return u.d2 != v.d2 ? u.d2 < v.d2 : u.key < v.key; });
  double best_d2 = radius * radius, best_d = radius;
  std::uint32_t best_kept = 0;
  auto visit = [&](std::uint32_t t) {
    const glm::dvec3 q = closest_on_triangle(p, m.a[t], m.b[t], m.c[t]);
    const double d2 = glm::dot(q - p, q - p);
    if (d2 < best_d2 || (d2 == best_d2 && best.found && t < best_kept)) {
      best_d2 = d2, best_d = std::sqrt(d2), best_kept = t, best.found = true, best.point = q;
    }
  };
  // The answer is the smallest (distance, index) within the radius, whatever the order of visits. So first the
  // triangle of the nearest cell whose sphere's centre lies nearest: its distance is most often the answer's or
  // near it, and the spheres then pass over almost every other triangle.
  if (count > 0) {
    const auto first = m.cells.find(cells[0].key);
    if (first != m.cells.end()) visit(nearest_sphere(m, first->second, p));
  }
  for (std::size_t i = 0; i < count; ++i) {
    // Every point of a triangle lies in a cell it is filed under (its bounding box's cells), so a cell farther than
    // the best so far holds no point nearer, nor does any after it. The 1e-6 mm margin is far above the rounding of
    // the cells' corners.
    const double reach_cell = best_d + 1e-6;
    if (cells[i].d2 > reach_cell * reach_cell) break;
    const auto it = m.cells.find(cells[i].key);
    if (it == m.cells.end()) continue;
    for (std::size_t e = it->second.first; e < it->second.second; ++e) {
      const std::uint32_t t = m.filed[e];
      // Every point of the triangle lies farther than best_d when its sphere does: passing over it changes nothing
      // (the sphere holds the triangle, bounding_sphere), and saves the closest point, which most triangles of the
      // cells searched would fail.
      const CellEntry& sphere = m.sphere[t];
      const glm::dvec3 to_centre = p - glm::dvec3(sphere.x, sphere.y, sphere.z);
      const double reach = best_d + sphere.bound;
      if (glm::dot(to_centre, to_centre) > reach * reach) continue;
      visit(t);
    }
  }
  if (!best.found) return best;
  best.normal = m.normal[best_kept];
  best.distance = std::sqrt(best_d2);
  best.triangle = m.index[best_kept];
  return best;
}

SurfaceModel::SurfaceModel(const std::vector<ObjectSurface>& surfaces, double cell_mm, const PadGeometry& pad)
    : SurfaceModel(surfaces, cell_mm) {
  if (pad.rows <= 0 || pad.cols <= 0 || !(pad.pitch_mm > 0.0) || !(pad.contact_depth_mm >= 0.0) ||
      !(pad.reach_mm > 0.0))
    throw Error("surface model: the pad needs rows, columns, a pitch and a reach, and a contact depth >= 0");
  pad_ = pad;
  pad_.reach_mm = std::min(pad.reach_mm, cell_);
}

namespace {

// The plane o + a u + b v of least squares through (u, v, z) over `use`, its slopes held near 0 by `ridge` (a pad of
// two elements in contact fixes no tilt). Returns {o, a, b}.
glm::dvec3 fit_plane(const std::vector<glm::dvec3>& uvz, const std::vector<char>& use, double ridge) {
  glm::dmat3 a(0.0);
  glm::dvec3 b(0.0);
  for (std::size_t k = 0; k < uvz.size(); ++k) {
    if (!use[k]) continue;
    const glm::dvec3 row(1.0, uvz[k].x, uvz[k].y);
    a += glm::outerProduct(row, row);
    b += row * uvz[k].z;
  }
  a[1][1] += ridge, a[2][2] += ridge;
  if (!(a[0][0] > 0.0)) return glm::dvec3(0.0);
  return glm::inverse(a) * b;
}

}  // namespace

double SurfaceModel::pad_misfit(std::uint32_t object, const ObservedReading& r, const RigidPose& pose) const {
  const std::size_t elements = static_cast<std::size_t>(pad_.rows) * static_cast<std::size_t>(pad_.cols);
  if (!has_pad() || r.depth_mm.size() != elements || object >= meshes_.size()) return -1.0;
  const glm::dvec3 n = glm::normalize(r.normal);
  glm::dvec3 x = r.x_axis - glm::dot(r.x_axis, n) * n;
  if (!(glm::length(x) > 1e-6)) return -1.0;
  x = glm::normalize(x);
  const glm::dvec3 y = glm::cross(n, x);
  const glm::dmat3 Rt = glm::transpose(pose.R);
  const glm::dvec3 no = Rt * n;
  // Per element: its place on the pad (u, v) and how far the surface lies below the pad's plane there (its height
  // above the surface: negative where the surface pokes through, as under a pressing pad), the reach where none is.
  std::vector<glm::dvec3> uvh(elements);
  for (int i = 0; i < pad_.rows; ++i)
    for (int j = 0; j < pad_.cols; ++j) {
      const double u = (j - 0.5 * (pad_.cols - 1)) * pad_.pitch_mm, v = (i - 0.5 * (pad_.rows - 1)) * pad_.pitch_mm;
      const glm::dvec3 c = Rt * (r.position + u * x + v * y - pose.T);
      const Nearest q = nearest(object, c, pad_.reach_mm);
      uvh[static_cast<std::size_t>(i * pad_.cols + j)] = {u, v, q.found ? glm::dot(c - q.point, no) : pad_.reach_mm};
    }
  // The press plane: the elements felt, depth + height = o + a u + b v; then again over the elements the plane
  // predicts in contact too (a few rounds: the set settles).
  std::vector<char> use(elements, 0);
  std::vector<glm::dvec3> target(elements);
  for (std::size_t k = 0; k < elements; ++k) {
    use[k] = r.depth_mm[k] > pad_.contact_depth_mm;
    target[k] = {uvh[k].x, uvh[k].y, r.depth_mm[k] + uvh[k].z};
  }
  const double ridge = 0.5 * static_cast<double>(elements);  // mm^2 per unit slope^2: 2 degrees cost 0.02 mm^2
  glm::dvec3 plane = fit_plane(target, use, ridge);
  for (int round = 0; round < 3; ++round) {
    for (std::size_t k = 0; k < elements; ++k)
      use[k] = r.depth_mm[k] > pad_.contact_depth_mm ||
               plane.x + plane.y * uvh[k].x + plane.z * uvh[k].y - uvh[k].z > pad_.contact_depth_mm;
    plane = fit_plane(target, use, ridge);
  }
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < elements; ++k) {
    const double predicted = std::max(0.0, plane.x + plane.y * uvh[k].x + plane.z * uvh[k].y - uvh[k].z);
    if (!(r.depth_mm[k] > pad_.contact_depth_mm || predicted > pad_.contact_depth_mm)) continue;
    const double e = r.depth_mm[k] - predicted;
    sum += e * e;
    ++count;
  }
  return count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
}

double SurfaceModel::log2_likelihood(std::uint32_t object, const ObservedReading& r, const RigidPose& pose,
                                     const ContactNoise& noise) const {
  // The reading in the object's frame: the hypothesis says where the object is.
  const glm::dvec3 p = glm::transpose(pose.R) * (r.position - pose.T);
  const glm::dvec3 n = glm::transpose(pose.R) * r.normal;
  const Nearest q = nearest(object, p, noise.reach_mm);
  if (!q.found) return pmath::log2(noise.floor);
  const glm::dvec3 tilt = n - q.normal;
  double s2 = q.distance * q.distance + noise.normal_weight_mm * noise.normal_weight_mm * glm::dot(tilt, tilt);
  if (noise.pad_sigma_mm > 0.0) {
    const double misfit = pad_misfit(object, r, pose);
    const double scale = noise.sigma_mm / noise.pad_sigma_mm;
    if (misfit >= 0.0) s2 += scale * scale * misfit * misfit;
  }
  return pmath::log2(pmath::exp(-0.5 * s2 / (noise.sigma_mm * noise.sigma_mm)) + noise.floor);
}

double SurfaceModel::log2_likelihood(std::uint32_t object, std::span<const ObservedReading> readings,
                                     const RigidPose& pose, const ContactNoise& noise) const {
  double bits = 0.0;
  for (const ObservedReading& r : readings) bits += log2_likelihood(object, r, pose, noise);
  return bits;
}

}  // namespace sva
