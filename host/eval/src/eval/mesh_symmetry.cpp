#include <sva/eval/mesh_symmetry.hpp>

#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>
#include <sva/base/symmetric_eigen3.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

#include "eval/surface_distance.hpp"

namespace sva::eval {

namespace {

constexpr double kPi = std::numbers::pi;
// Two axes are one when they are within 1 degree; two rotations are one when R1^T R2 turns by less than 1 degree
// (the candidates come from a mesh's geometry, so products of them drift by its rounding, far below this).
const double kSameAxisCos = pmath::cos(kPi / 180.0);
constexpr double kSameRotation = kPi / 180.0;

// The eigenvectors of the symmetric scatter (columns): the principal axes of the surface.
glm::dmat3 principal_axes(const glm::dmat3& m) {
  std::array<std::array<double, 3>, 3> rows;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows[i][j] = m[j][i];  // glm is column-major: m[col][row]
  const SymmetricEigen3 e = symmetric_eigen3(rows);
  glm::dmat3 axes;
  for (int j = 0; j < 3; ++j) axes[j] = glm::normalize(glm::dvec3(e.vectors[0][j], e.vectors[1][j], e.vectors[2][j]));
  return axes;
}

// An axis up to its sign, made canonical (largest component positive) so that the candidates' order and the
// found axis do not depend on which way a computation happened to point it.
glm::dvec3 canonical(glm::dvec3 a) {
  a = glm::normalize(a);
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::fabs(a[i]) > std::fabs(a[k])) k = i;
  return a[k] < 0 ? -a : a;
}

void add_axis(std::vector<glm::dvec3>& axes, const glm::dvec3& a) {
  const double n = std::sqrt(glm::dot(a, a));
  if (!(n > 1e-9)) return;
  const glm::dvec3 u = canonical(a / n);
  for (const auto& b : axes)
    if (std::fabs(glm::dot(u, b)) > kSameAxisCos) return;
  axes.push_back(u);
}

// The directions (up to sign) that hold the most surface area, largest first: the normals of a box's faces.
std::vector<glm::dvec3> dominant_normals(const ObjectSurface& mesh, std::size_t count) {
  const double same = pmath::cos(2.0 * kPi / 180.0);
  std::vector<glm::dvec3> normals;
  std::vector<double> areas;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area2 = std::sqrt(glm::dot(n, n));
    if (!(area2 > 0.0)) continue;
    const glm::dvec3 u = canonical(n / area2);
    std::size_t k = 0;
    while (k < normals.size() && std::fabs(glm::dot(normals[k], u)) <= same) ++k;
    if (k == normals.size()) {
      if (normals.size() >= 256) continue;  // a curved surface: its normals name no face
      normals.push_back(u);
      areas.push_back(0.0);
    }
    areas[k] += area2;
  }
  std::vector<std::size_t> order(normals.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t i, std::size_t j) { return areas[i] != areas[j] ? areas[i] > areas[j] : i < j; });
  std::vector<glm::dvec3> out;
  for (std::size_t k = 0; k < std::min(count, order.size()); ++k) out.push_back(normals[order[k]]);
  return out;
}

// Where a symmetry axis can lie: the principal axes (enough for a body with distinct moments), and for a body
// whose moments coincide (a cube, a die) the axes its shape shows: the directions of its dominant faces and of its
// farthest vertices, and the bisectors of pairs of those (the half-turn axes through a cube's edges).
std::vector<glm::dvec3> candidate_axes(const ObjectSurface& mesh, const SurfaceDistance& surface,
                                       const glm::dmat3& principal) {
  std::vector<glm::dvec3> base;
  for (int j = 0; j < 3; ++j) add_axis(base, principal[j]);
  const std::vector<glm::dvec3>& v = surface.vertices();
  const glm::dvec3 c = surface.centroid();
  std::vector<std::size_t> far(v.size());
  std::iota(far.begin(), far.end(), std::size_t{0});
  std::sort(far.begin(), far.end(), [&](std::size_t i, std::size_t j) {
    const double di = glm::dot(v[i] - c, v[i] - c), dj = glm::dot(v[j] - c, v[j] - c);
    return di != dj ? di > dj : i < j;
  });
  std::vector<glm::dvec3> shape;
  for (std::size_t k = 0; k < far.size() && shape.size() < 8; ++k) add_axis(shape, v[far[k]] - c);
  for (const glm::dvec3& n : dominant_normals(mesh, 6)) add_axis(shape, n);
  std::vector<glm::dvec3> axes = base;
  for (const auto& a : shape) add_axis(axes, a);
  const std::size_t n = std::min<std::size_t>(axes.size(), 24);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      add_axis(axes, axes[i] + axes[j]);
      add_axis(axes, axes[i] - axes[j]);
    }
  return axes;
}

class Checker {
 public:
  Checker(const SurfaceDistance& surface, const std::vector<glm::dvec3>& points, double tolerance)
      : surface_(surface), points_(points), tolerance_(tolerance) {}

  // The largest distance from the turned points to the surface, or a value above the tolerance as soon as one
  // point lies beyond it (most candidates fail on their first points).
  double worst(const glm::dmat3& S, std::size_t count) const {
    const glm::dvec3 c = surface_.centroid();
    double worst = 0.0;
    for (std::size_t i = 0; i < std::min(count, points_.size()); ++i) {
      worst = std::max(worst, surface_.distance(S * (points_[i] - c) + c, 2.0 * tolerance_));
      if (worst > tolerance_) break;
    }
    return worst;
  }
  // The first 100 points (a random subset: the samples are drawn at random) turn most candidates down at a
  // twentieth of the cost of all of them.
  bool passes_quick_look(const glm::dmat3& S) const { return worst(S, 100) <= tolerance_; }
  bool accepts(const glm::dmat3& S, double* worst_seen) const {
    const double w = worst(S, points_.size());
    if (w > tolerance_) return false;
    *worst_seen = std::max(*worst_seen, w);
    return true;
  }

 private:
  const SurfaceDistance& surface_;
  const std::vector<glm::dvec3>& points_;
  double tolerance_;
};

// Continuous about `axis`: a symmetry at several angles that no small order shares (BOP checks a continuous
// symmetry the same way, at its discretisation's steps).
bool continuous_about(const Checker& check, const glm::dvec3& axis, double* worst) {
  for (double g : {3.0, 2.0, 0.37, 1.13, 2.71})
    if (!check.passes_quick_look(so3::about_axis(axis, g))) return false;
  double w = *worst;  // only an axis that passes at every angle counts towards the worst accepted distance
  for (double g : {3.0, 2.0, 0.37, 1.13, 2.71})
    if (!check.accepts(so3::about_axis(axis, g), &w)) return false;
  *worst = w;
  return true;
}

// The orders n <= max_order, largest first, of which every turn about `axis` is a symmetry, leaving out the divisors
// of one found (implied). Within a tolerance a turn can pass that is no divisor of another (a knurl of 36 ridges
// turned by 1/54 of a turn moves its surface less than the tolerance), so every order is tried, not only the largest.
std::vector<int> orders_about(const Checker& check, const glm::dvec3& axis, int max_order, double* worst) {
  std::vector<int> found;
  for (int n = max_order; n >= 2; --n) {
    bool implied = false;
    for (int m : found) implied = implied || m % n == 0;
    if (implied) continue;
    double w = *worst;
    bool all = true;
    // The half-way turns first: they move the surface farthest, so a non-symmetry fails on them soonest.
    for (int k = n / 2; k >= 1 && all; --k) all = check.passes_quick_look(so3::about_axis(axis, 2.0 * kPi * k / n));
    for (int k = 1; k < n && all; ++k) all = check.accepts(so3::about_axis(axis, 2.0 * kPi * k / n), &w);
    if (all) {
      *worst = w;
      found.push_back(n);
    }
  }
  return found;
}

bool contains(const std::vector<glm::dmat3>& set, const glm::dmat3& R) {
  for (const auto& S : set)
    if (so3::angle_sincos(glm::transpose(S) * R) < kSameRotation) return true;
  return false;
}

// The group the generators make (products until nothing new, at most `cap` elements: 60 is the icosahedron's,
// the largest finite group of rotations of a solid but the dihedral ones, 2n), each product checked against the
// surface, identity first.
std::vector<glm::dmat3> close_group(const std::vector<glm::dmat3>& generators, const Checker& check, std::size_t cap,
                                    double* worst) {
  std::vector<glm::dmat3> group{glm::dmat3(1.0)}, used;
  for (const glm::dmat3& next : generators) {
    if (contains(group, next)) continue;  // the generators so far make it already: most candidates do
    used.push_back(next);
    for (std::size_t i = 0; i < group.size() && group.size() < cap; ++i)
      for (const auto& g : used) {
        const glm::dmat3 R = so3::orthonormalize(g * group[i]);
        if (group.size() < cap && !contains(group, R) && check.passes_quick_look(R) && check.accepts(R, worst))
          group.push_back(R);
      }
  }
  return group;
}

// A half turn about an axis across the continuous `axis` that is a symmetry (the tyre turned over), if any. Every
// symmetry of a body of revolution keeps its axis or turns it over; all that turn it over are one such half turn
// composed with turns about the axis, so one is all MSSD needs. The axes across: the candidates' parts across
// `axis`, and two fixed ones.
std::optional<glm::dmat3> half_turn_across(const Checker& check, const glm::dvec3& axis,
                                           const std::vector<glm::dvec3>& candidates, double* worst) {
  std::vector<glm::dvec3> across;
  for (const glm::dvec3& c : candidates) add_axis(across, c - axis * glm::dot(c, axis));
  add_axis(across, glm::cross(axis, glm::dvec3(1, 0, 0)));
  add_axis(across, glm::cross(axis, glm::dvec3(0, 1, 0)));
  for (const glm::dvec3& b : across) {
    if (std::fabs(glm::dot(b, axis)) > 1e-6) continue;
    const glm::dmat3 F = so3::about_axis(b, kPi);
    if (check.passes_quick_look(F) && check.accepts(F, worst)) return F;
  }
  return std::nullopt;
}

std::string axis_text(const glm::dvec3& a) {
  char buf[96];
  // Components that print as 0 print as 0, not -0.
  const auto c = [](double v) { return std::fabs(v) < 0.005 ? 0.0 : v; };
  std::snprintf(buf, sizeof buf, "(%.2f, %.2f, %.2f)", c(a.x), c(a.y), c(a.z));
  return buf;
}

}  // namespace

std::string MeshSymmetry::describe() const {
  if (only_identity()) return "none";
  if (axis) return "continuous about " + axis_text(*axis) + (rotations.size() > 1 ? " and turned over" : "");
  // The axis most rotations turn about, its order, and the half turns across it: the words of a cyclic or
  // dihedral group, which most objects' are.
  std::vector<glm::dvec3> axes;
  std::vector<std::size_t> counts;
  for (std::size_t k = 1; k < rotations.size(); ++k) {
    const glm::dvec3 u = canonical(so3::log_sincos(rotations[k]));
    std::size_t i = 0;
    while (i < axes.size() && std::fabs(glm::dot(axes[i], u)) <= kSameAxisCos) ++i;
    if (i == axes.size()) {
      axes.push_back(u);
      counts.push_back(0);
    }
    ++counts[i];
  }
  const std::size_t main = static_cast<std::size_t>(std::max_element(counts.begin(), counts.end()) - counts.begin());
  std::string s = std::to_string(rotations.size()) + " rotations: " + std::to_string(counts[main] + 1) +
                  "-fold about " + axis_text(axes[main]);
  std::size_t across = 0;
  for (std::size_t i = 0; i < axes.size(); ++i) across += i != main && std::fabs(glm::dot(axes[i], axes[main])) < 0.02;
  if (across > 0) s += ", half turns about " + std::to_string(across) + " axes across it";
  if (axes.size() > 1 + across) s += ", turns about " + std::to_string(axes.size() - 1 - across) + " other axes";
  return s;
}

MeshSymmetry find_symmetries(const ObjectSurface& surface, const std::string& what, const SymmetrySearch& search) {
  return find_symmetries(surface, SurfaceDistance(surface, what), search);
}

MeshSymmetry find_symmetries(const ObjectSurface& surface, const SurfaceDistance& mesh, const SymmetrySearch& search) {
  if (!(search.tolerance_fraction > 0.0 && search.tolerance_fraction < 1.0))
    throw Error("symmetry search: the tolerance must be a fraction of the diameter in (0, 1), got " +
                std::to_string(search.tolerance_fraction));
  if (search.max_order < 2 || search.max_order > 360)
    throw Error("symmetry search: the largest order must be 2 to 360, got " + std::to_string(search.max_order));
  if (search.samples < 10)
    throw Error("symmetry search: at least 10 surface points are needed, got " + std::to_string(search.samples));
  MeshSymmetry out;
  out.centre = mesh.centroid();
  out.diameter_mm = mesh.diameter();
  out.tolerance_mm = search.tolerance_fraction * out.diameter_mm;
  const std::vector<glm::dvec3> points = mesh.sample(search.samples, search.seed);
  const Checker check(mesh, points, out.tolerance_mm);
  const std::vector<glm::dvec3> axes = candidate_axes(surface, mesh, principal_axes(mesh.scatter()));
  for (const glm::dvec3& a : axes)
    if (continuous_about(check, a, &out.worst_accepted_mm)) {
      out.axis = a;
      if (const auto flip = half_turn_across(check, a, axes, &out.worst_accepted_mm)) out.rotations.push_back(*flip);
      return out;
    }
  std::vector<glm::dmat3> generators;
  for (const glm::dvec3& a : axes)
    for (int n : orders_about(check, a, search.max_order, &out.worst_accepted_mm)) {
      const glm::dmat3 g = so3::about_axis(a, 2.0 * kPi / n);
      if (!contains(generators, g)) generators.push_back(g);
    }
  out.rotations = close_group(generators, check, static_cast<std::size_t>(std::max(60, 2 * search.max_order)),
                              &out.worst_accepted_mm);
  return out;
}

namespace {

// The rotations of the scene's declared symmetry that the mesh does not have, as words ("" when it has them all).
std::string declared_but_not_found(const Symmetry& declared, const MeshSymmetry& found) {
  if (declared.kind == Symmetry::Kind::none) return "";
  const glm::dvec3 a = canonical(declared.axis);
  if (found.axis && std::fabs(glm::dot(*found.axis, a)) > kSameAxisCos) return "";
  if (declared.kind == Symmetry::Kind::axis) return "every turn about " + axis_text(a);
  const std::vector<glm::dmat3> all = symmetry_rotations(found);
  for (const glm::dmat3& S : declared.rotations)
    if (!contains(all, S)) return std::to_string(declared.rotations.size()) + "-fold about " + axis_text(a);
  return "";
}

// A rotation the scene's declared symmetry holds.
bool declares(const Symmetry& declared, const glm::dmat3& R) {
  switch (declared.kind) {
    case Symmetry::Kind::none:
      return so3::angle_sincos(R) < kSameRotation;
    case Symmetry::Kind::axis: {
      const glm::dvec3 r = so3::log_sincos(R);
      const double angle = std::sqrt(glm::dot(r, r));
      return angle < kSameRotation || std::fabs(glm::dot(r / angle, glm::normalize(declared.axis))) > kSameAxisCos;
    }
    case Symmetry::Kind::discrete:
      return contains(declared.rotations, R);
  }
  return false;
}

// The mesh's symmetries that the scene leaves out, as words ("" when it declares them all).
std::string found_but_not_declared(const Symmetry& declared, const MeshSymmetry& found) {
  std::string out;
  if (found.axis) {
    const bool declared_axis = declared.kind != Symmetry::Kind::none &&
                               std::fabs(glm::dot(*found.axis, canonical(declared.axis))) > kSameAxisCos;
    if (!(declared_axis && declared.kind == Symmetry::Kind::axis)) out = "every turn about " + axis_text(*found.axis);
  }
  std::size_t missing = 0;
  for (const glm::dmat3& S : found.rotations) missing += !declares(declared, S);
  if (missing > 0) {
    if (!out.empty()) out += " and ";
    out += found.axis ? "a half turn that turns it over"
                      : std::to_string(missing) + " of its " + std::to_string(found.rotations.size()) + " rotations";
  }
  return out;
}

std::string declared_text(const Symmetry& s) {
  switch (s.kind) {
    case Symmetry::Kind::none:
      return "none";
    case Symmetry::Kind::axis:
      return "axis " + axis_text(canonical(s.axis));
    case Symmetry::Kind::discrete:
      return "cyclic order " + std::to_string(s.rotations.size()) + " about " + axis_text(canonical(s.axis));
  }
  return "?";
}

}  // namespace

std::string symmetry_disagreement(const SceneObject& object, const MeshSymmetry& found) {
  const std::string lacks = declared_but_not_found(object.symmetry, found);
  const std::string extra = found_but_not_declared(object.symmetry, found);
  if (lacks.empty() && extra.empty()) return "";
  char tol[64];
  std::snprintf(tol, sizeof tol, "%.2f mm", found.tolerance_mm);
  std::string s = "object \"" + object.name + "\": the scene declares symmetry " + declared_text(object.symmetry) +
                  ", its mesh has " + found.describe() + " (within " + tol + ")";
  if (!lacks.empty()) s += "; the mesh lacks " + lacks;
  if (!extra.empty()) s += "; the scene leaves out " + extra + " (the angle error counts those copies as errors)";
  return s;
}

std::vector<glm::dmat3> symmetry_rotations(const MeshSymmetry& found, double step_fraction) {
  if (!found.axis) return found.rotations;
  // bop_toolkit misc.get_symmetry_transformations: ceil(pi / step) turns, so that a point at most half the
  // diameter from the axis moves at most step * diameter between two of them.
  const int steps = static_cast<int>(std::ceil(kPi / step_fraction));
  std::vector<glm::dmat3> out;
  for (const glm::dmat3& D : found.rotations)
    for (int k = 0; k < steps; ++k) out.push_back(so3::about_axis(*found.axis, 2.0 * kPi * k / steps) * D);
  return out;
}

}  // namespace sva::eval
