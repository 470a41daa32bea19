// The shared construction helpers of the generated objects (mesh_builder.hpp).
#include "mesh_builder.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace sva::assets {

double smoothstep(double a, double b, double x) {
  double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}
double fract(double x) { return x - std::floor(x); }

glm::dmat3 rot_x(double deg) {
  double a = deg * kPi / 180;
  return glm::dmat3(dvec3(1, 0, 0), dvec3(0, std::cos(a), std::sin(a)), dvec3(0, -std::sin(a), std::cos(a)));
}
glm::dmat3 rot_y(double deg) {
  double a = deg * kPi / 180;
  return glm::dmat3(dvec3(std::cos(a), 0, -std::sin(a)), dvec3(0, 1, 0), dvec3(std::sin(a), 0, std::cos(a)));
}
glm::dmat3 rot_z(double deg) {
  double a = deg * kPi / 180;
  return glm::dmat3(dvec3(std::cos(a), std::sin(a), 0), dvec3(-std::sin(a), std::cos(a), 0), dvec3(0, 0, 1));
}

ShellMark mark(const Mesh& m) { return {m.positions.size(), m.triangles.size()}; }

void place(Mesh& m, ShellMark from, const glm::dmat3& linear, dvec3 offset) {
  for (std::size_t i = from.vertices; i < m.positions.size(); ++i)
    m.positions[i] = glm::vec3(offset + linear * dvec3(m.positions[i]));
  if (glm::determinant(linear) < 0)
    for (std::size_t i = from.triangles; i < m.triangles.size(); ++i) std::swap(m.triangles[i].y, m.triangles[i].z);
}

void add_grid(Mesh& m, int nu, int nv, bool wrap_u, bool wrap_v, const std::function<dvec3(double, double)>& p) {
  const int cu = wrap_u ? nu : nu + 1, cv = wrap_v ? nv : nv + 1;
  const auto base = static_cast<unsigned>(m.positions.size());
  for (int j = 0; j < cv; ++j)
    for (int i = 0; i < cu; ++i) m.positions.emplace_back(p(static_cast<double>(i) / nu, static_cast<double>(j) / nv));
  auto id = [&](int i, int j) { return base + static_cast<unsigned>((j % cv) * cu + (i % cu)); };
  auto tri = [&](unsigned a, unsigned b, unsigned c) {
    dvec3 A(m.positions[a]), B(m.positions[b]), C(m.positions[c]);
    if (glm::length(glm::cross(B - A, C - A)) > 1e-9) m.triangles.emplace_back(a, b, c);
  };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      tri(a, b, c);
      tri(a, c, d);
    }
}

void add_revolution(Mesh& m, const std::vector<ProfilePoint>& profile, int n_theta, bool closed_loop, dvec3 centre,
                    const std::function<double(double theta, double r, double z)>& dr) {
  std::vector<dvec2> pts;  // resampled (r, z)
  pts.push_back({profile[0].r, profile[0].z});
  for (std::size_t k = 1; k < profile.size(); ++k)
    for (int s = 1; s <= profile[k].segments; ++s) {
      double t = static_cast<double>(s) / profile[k].segments;
      pts.push_back({profile[k - 1].r + t * (profile[k].r - profile[k - 1].r),
                     profile[k - 1].z + t * (profile[k].z - profile[k - 1].z)});
    }
  if (closed_loop) pts.pop_back();  // the last point repeats the first
  const int nv = closed_loop ? static_cast<int>(pts.size()) : static_cast<int>(pts.size()) - 1;
  add_grid(m, n_theta, nv, true, closed_loop, [&](double u, double v) {
    int k = static_cast<int>(std::lround(v * nv)) % static_cast<int>(pts.size());
    double th = 2 * kPi * u, r = pts[static_cast<std::size_t>(k)].x, z = pts[static_cast<std::size_t>(k)].y;
    if (dr && r > 1e-9) r = std::max(0.0, r + dr(th, r, z));
    return centre + dvec3(r * std::cos(th), r * std::sin(th), z);
  });
}

void curve(Profile& p, int n, const std::function<dvec2(double)>& f) {
  for (int k = 1; k <= n; ++k) {
    dvec2 q = f(static_cast<double>(k) / n);
    p.push_back({q.x, q.y, 1});
  }
}

Profile polar_profile(double cz, int n, const std::function<double(double)>& rho) {
  Profile p{{0, cz - rho(0), 0}};
  curve(p, n, [&](double s) {
    double a = kPi * s;
    return dvec2(s < 1 ? rho(a) * std::sin(a) : 0.0, cz - rho(a) * std::cos(a));
  });
  return p;
}

Profile vessel(const Profile& outside, double wall, double floor) {
  Profile p = outside;
  const ProfilePoint rim = outside.back();
  p.push_back({rim.r - wall, rim.z, 2});
  for (std::size_t k = outside.size() - 1; k-- > 0;) {
    const ProfilePoint &q = outside[k], &above = outside[k + 1];
    if (q.z > floor) {
      p.push_back({q.r - wall, q.z, above.segments});
      continue;
    }
    double t = (floor - q.z) / (above.z - q.z);  // where the outside crosses the floor's height
    p.push_back({q.r + t * (above.r - q.r) - wall, floor, above.segments});
    break;
  }
  p.push_back({0, floor, 6});
  return p;
}

namespace {
struct BoxFace {
  dvec3 n, a, b;
  double hn, ha, hb;
};
// The six faces of a box of half sizes h, each with a x b = n.
std::array<BoxFace, 6> box_faces(dvec3 h) {
  const dvec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  return {{{X, Y, Z, h.x, h.y, h.z},
           {-X, Z, Y, h.x, h.z, h.y},
           {Y, Z, X, h.y, h.z, h.x},
           {-Y, X, Z, h.y, h.x, h.z},
           {Z, X, Y, h.z, h.x, h.y},
           {-Z, Y, X, h.z, h.y, h.x}}};
}
}  // namespace

void add_box(Mesh& m, dvec3 c, dvec3 h, double cell, const std::function<double(int face, double s, double t)>& disp,
             const glm::dmat3& rot) {
  const auto faces = box_faces(h);
  for (int f = 0; f < 6; ++f) {
    const BoxFace& F = faces[static_cast<std::size_t>(f)];
    int nu = std::max(1, static_cast<int>(std::ceil(2 * F.ha / cell))),
        nv = std::max(1, static_cast<int>(std::ceil(2 * F.hb / cell)));
    add_grid(m, nu, nv, false, false, [&](double u, double v) {
      double s = (u - 0.5) * 2 * F.ha, t = (v - 0.5) * 2 * F.hb;
      double d = disp ? disp(f, s, t) : 0.0;
      return c + rot * (F.n * (F.hn + d) + F.a * s + F.b * t);
    });
  }
}

namespace {
// One axis of a rounded box's face grid: `round` cells in each end band of
// width r (equal steps of angle round the edge), the flat middle in cells of
// about `cell` mm. Mirrored samples are computed alike, so that the faces that
// meet at an edge put their vertices at the same points.
struct RoundedAxis {
  double half, r;
  int round, mid;
  RoundedAxis(double half_, double r_, double cell, int round_)
      : half(half_), r(r_), round(round_), mid(std::max(1, static_cast<int>(std::ceil(2 * (half_ - r_) / cell)))) {}
  int cells() const { return 2 * round + mid; }
  double at(int i) const {
    const int n = cells();
    if (2 * i > n) return -at(n - i);
    if (i < round) return -(half - r) - r * std::tan(kPi / 4 * (round - i) / round);
    return -(half - r) + 2 * (half - r) * (i - round) / mid;
  }
};
}  // namespace

void add_rounded_box(Mesh& m, dvec3 h, double r, double cell, int round_segments) {
  if (!(r > 0) || r >= std::min({h.x, h.y, h.z})) throw Error("add_rounded_box: radius must be below every half size");
  const dvec3 inner = h - dvec3(r);
  for (const BoxFace& F : box_faces(h)) {
    RoundedAxis A(F.ha, r, cell, round_segments), B(F.hb, r, cell, round_segments);
    add_grid(m, A.cells(), B.cells(), false, false, [&](double u, double v) {
      double s = A.at(static_cast<int>(std::lround(u * A.cells())));
      double t = B.at(static_cast<int>(std::lround(v * B.cells())));
      dvec3 q = F.n * F.hn + F.a * s + F.b * t;  // on the sharp box
      dvec3 core = glm::clamp(q, -inner, inner);
      return core + r * glm::normalize(q - core);
    });
  }
}

void add_torus(Mesh& m, dvec3 c, dvec3 e1, dvec3 e2, double R, double r, int nu, int nv) {
  dvec3 e3 = glm::cross(e1, e2);
  add_grid(m, nu, nv, true, true, [&](double u, double v) {
    double th = 2 * kPi * u, ph = 2 * kPi * v;
    dvec3 rho = std::cos(th) * e1 + std::sin(th) * e2;
    return c + (R + r * std::cos(ph)) * rho + r * std::sin(ph) * e3;
  });
}

void add_sweep(Mesh& m, const Sweep& s) {
  struct Row {
    double t, scale;
  };
  std::vector<Row> rows;
  if (s.flat_caps) rows.push_back({0, 0});
  for (int k = 0; k <= s.n_t; ++k) rows.push_back({static_cast<double>(k) / s.n_t, 1});
  if (s.flat_caps) rows.push_back({1, 0});
  const dvec3 up = glm::normalize(s.up);
  const int nv = static_cast<int>(rows.size()) - 1;
  add_grid(m, s.n_phi, nv, true, false, [&](double u, double v) {
    const Row& row = rows[static_cast<std::size_t>(std::lround(v * nv))];
    const double h = 1e-4, t0 = std::max(0.0, row.t - h), t1 = std::min(1.0, row.t + h);
    dvec3 side = glm::normalize(glm::cross(up, s.path(t1) - s.path(t0)));
    double phi = 2 * kPi * u, rad = row.scale * s.radius(row.t);
    return s.path(row.t) + rad * (std::cos(phi) * side + s.flatten * std::sin(phi) * up);
  });
}

void add_handle(Mesh& m, dvec3 top, dvec3 bottom, double reach, double radius, double flatten) {
  Sweep s;
  s.path = [=](double t) {
    double w = 0.5 * (1 - std::cos(kPi * t));
    return dvec3(top.x + (bottom.x - top.x) * w + reach * std::sin(kPi * t), 0.0,
                 0.5 * (top.z + bottom.z) + 0.5 * (top.z - bottom.z) * std::cos(kPi * t));
  };
  s.up = {0, 1, 0};
  s.radius = [=](double) { return radius; };
  s.flatten = flatten;
  s.n_t = 28;
  s.n_phi = 14;
  add_sweep(m, s);
}

namespace {
double cross2(dvec2 a, dvec2 b) { return a.x * b.y - a.y * b.x; }

bool in_triangle(dvec2 p, dvec2 a, dvec2 b, dvec2 c) {
  return cross2(b - a, p - a) >= 0 && cross2(c - b, p - b) >= 0 && cross2(a - c, p - c) >= 0;
}

// Ear clipping of a counter-clockwise simple polygon: triangles as index triples.
std::vector<glm::uvec3> triangulate(const std::vector<dvec2>& poly) {
  std::vector<unsigned> left(poly.size());
  std::iota(left.begin(), left.end(), 0u);
  std::vector<glm::uvec3> out;
  while (left.size() > 3) {
    bool clipped = false;
    for (std::size_t k = 0; k < left.size() && !clipped; ++k) {
      unsigned i0 = left[(k + left.size() - 1) % left.size()], i1 = left[k], i2 = left[(k + 1) % left.size()];
      dvec2 a = poly[i0], b = poly[i1], c = poly[i2];
      if (cross2(b - a, c - b) <= 1e-12) continue;  // reflex or straight: not an ear
      bool empty = true;
      for (unsigned j : left)
        if (j != i0 && j != i1 && j != i2 && in_triangle(poly[j], a, b, c)) empty = false;
      if (!empty) continue;
      out.emplace_back(i0, i1, i2);
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) throw Error("add_extrusion: the outline is not a simple polygon");
  }
  out.emplace_back(left[0], left[1], left[2]);
  return out;
}
}  // namespace

void add_extrusion(Mesh& m, const std::vector<dvec2>& outline, double z0, double z1, int rows) {
  std::vector<dvec2> poly = outline;
  double area = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) area += cross2(poly[i], poly[(i + 1) % poly.size()]);
  if (area < 0) std::reverse(poly.begin(), poly.end());
  const auto n = static_cast<unsigned>(poly.size());
  const auto base = static_cast<unsigned>(m.positions.size());
  for (int k = 0; k <= rows; ++k)
    for (const dvec2& p : poly) m.positions.emplace_back(p.x, p.y, z0 + (z1 - z0) * k / rows);
  auto id = [&](int k, unsigned i) { return base + static_cast<unsigned>(k) * n + i % n; };
  for (int k = 0; k < rows; ++k)
    for (unsigned i = 0; i < n; ++i) {
      m.triangles.emplace_back(id(k, i), id(k, i + 1), id(k + 1, i + 1));
      m.triangles.emplace_back(id(k, i), id(k + 1, i + 1), id(k + 1, i));
    }
  for (const glm::uvec3& t : triangulate(poly)) {
    m.triangles.emplace_back(id(rows, t.x), id(rows, t.y), id(rows, t.z));
    m.triangles.emplace_back(id(0, t.x), id(0, t.z), id(0, t.y));
  }
}

void append_arc(std::vector<dvec2>& out, dvec2 centre, double radius, double from_deg, double to_deg, int n) {
  for (int k = 0; k <= n; ++k) {
    double a = (from_deg + (to_deg - from_deg) * k / n) * kPi / 180;
    out.push_back(centre + radius * dvec2(std::cos(a), std::sin(a)));
  }
}

std::vector<dvec2> regular_polygon(int sides, double radius, double start_deg) {
  std::vector<dvec2> out;
  append_arc(out, {0, 0}, radius, start_deg, start_deg + 360.0 * (sides - 1) / sides, sides - 1);
  return out;
}

}  // namespace sva::assets
