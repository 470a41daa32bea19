#include "estimate/surface_model.hpp"

#include <sva/base/finite.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace sva {

SurfaceModel::SurfaceModel(const std::vector<ObjectSurface>& surfaces, double reach_mm) : reach_(reach_mm) {
  if (!(reach_mm > 0.0) || !std::isfinite(reach_mm)) throw Error("surface model: the reach must be positive");
  meshes_.resize(surfaces.size());
  for (std::size_t o = 0; o < surfaces.size(); ++o) {
    const ObjectSurface& s = surfaces[o];
    Mesh& m = meshes_[o];
    std::vector<TriangleTree::Triangle> kept;
    for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
      const glm::uvec3 tri = s.triangles[t];
      const auto fault = [&](const char* what) {
        return Error("surface model: triangle " + std::to_string(t) + " of object " + std::to_string(o) + " " + what);
      };
      if (std::max({tri.x, tri.y, tri.z}) >= s.positions.size()) throw fault("indexes a vertex the surface lacks");
      const glm::vec3 fa = s.positions[tri.x], fb = s.positions[tri.y], fc = s.positions[tri.z];
      const glm::dvec3 p(fa), q(fb), r(fc);
      if (!finite(p) || !finite(q) || !finite(r)) throw fault("has a corner that is not finite");
      const glm::dvec3 n = glm::cross(q - p, r - p);
      const double len = glm::length(n);
      if (!(len > 0.0)) continue;  // a degenerate triangle has no side to touch
      kept.push_back({fa, fb, fc, static_cast<std::uint32_t>(m.normal.size())});
      m.normal.push_back(n / len), m.index.push_back(t);
    }
    m.tree = TriangleTree(std::move(kept));
  }
}

SurfaceModel::Nearest SurfaceModel::nearest(std::uint32_t object, const glm::dvec3& p, double radius) const {
  Nearest best;
  if (object >= meshes_.size()) return best;
  const Mesh& m = meshes_[object];
  const TriangleTree::Hit hit = m.tree.nearest(p, std::min(radius, reach_));
  if (!hit.found) return best;
  best.found = true;
  best.point = hit.point;
  best.normal = m.normal[hit.index];
  best.distance = std::sqrt(hit.d2);
  best.d2 = hit.d2;
  best.triangle = m.index[hit.index];
  return best;
}

SurfaceModel::SurfaceModel(const std::vector<ObjectSurface>& surfaces, double reach_mm, const PadGeometry& pad)
    : SurfaceModel(surfaces, reach_mm) {
  if (pad.rows <= 0 || pad.cols <= 0 || !(pad.pitch_mm > 0.0) || !(pad.contact_depth_mm >= 0.0) ||
      !(pad.reach_mm > 0.0))
    throw Error("surface model: the pad needs rows, columns, a pitch and a reach, and a contact depth >= 0");
  pad_ = pad;
  pad_.reach_mm = std::min(pad.reach_mm, reach_);
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
