// The objects of the paper's experiments: ten everyday objects whose surfaces
// differ in shape and in texture (ridges, knurling, tread, bumps, keys,
// dimples, edges, flat faces), in the spirit of the Princeton set of Sec 5.1
// (the paper3d scene rescales them to 80 mm), and the raised capital vowels
// of Sec 5.2.
#include "objects.hpp"

#include <algorithm>
#include <cmath>

namespace sva::assets {

namespace {

// ---- the ten objects --------------------------------------------------------

Mesh glass() {  // a tumbler with flutes round its lower half, open at the top
  Mesh m;
  add_revolution(m, {{0, 0, 0}, {30, 0, 8}, {34, 95, 90}, {32, 95, 2}, {28.5, 6, 40}, {0, 6, 8}}, 160, false, {},
                 [](double th, double r, double z) {
                   if (r < 29.9 || z < 4 || z > 55) return 0.0;  // outer wall only
                   double f = std::pow(std::max(0.0, std::cos(20 * th)), 2);
                   return -1.2 * f * smoothstep(4, 8, z) * (1 - smoothstep(50, 55, z));
                 });
  return m;
}

Mesh tyre() {  // a tyre with block tread and a centre groove
  Mesh m;
  add_revolution(m,
                 {{24, -13, 0},
                  {38, -13, 10},
                  {40, -11, 2},
                  {40, 11, 30},
                  {38, 13, 2},
                  {24, 13, 10},
                  {22, 11, 2},
                  {22, -11, 14},
                  {24, -13, 2}},
                 256, true, {}, [](double th, double r, double z) {
                   if (r < 39.9) return 0.0;
                   double lateral = fract(th * 48 / (2 * kPi) + 0.04 * z);
                   bool groove = std::abs(z) < 1.2 || lateral < 0.22;
                   return groove ? -1.8 : 0.0;
                 });
  return m;
}

Mesh screwdriver() {  // fluted handle with grip rings, round shaft, flat blade
  Mesh m;
  add_revolution(m,
                 {{0, 0, 0},
                  {11, 0, 6},
                  {12, 2, 2},
                  {12, 50, 70},
                  {10, 54, 3},
                  {4, 56, 4},
                  {3, 58, 2},
                  {3, 100, 20},
                  {2.6, 110, 8},
                  {1.2, 114, 3},
                  {0, 114, 2}},
                 128, false, {}, [](double th, double r, double z) {
                   if (z > 5 && z < 47 && r > 11.5) {
                     double flute = smoothstep(0.55, 0.85, std::cos(8 * th));
                     double ring = (z < 12 || z > 42) ? 0.0 : 0.5 * smoothstep(0.6, 0.9, std::cos(2 * kPi * z / 5));
                     return -1.5 * flute - ring;
                   }
                   if (z > 101) {  // flatten the blade to 1 mm thickness
                     double c = std::abs(std::cos(th));
                     double limit = c > 1e-6 ? 0.5 / c : 1e9;
                     return std::min(r, limit) - r;
                   }
                   return 0.0;
                 });
  return m;
}

Mesh phone() {  // a slab phone: recessed screen, 3 x 4 domed keys, camera bump
  Mesh m;
  add_box(m, {}, {18, 36, 4.5}, 0.55, [](int face, double s, double t) {
    if (face == 4) {  // +z: s along x, t along y
      double d = 0;
      if (std::abs(s) < 15 && t > 3 && t < 33)
        d -= 0.5 * smoothstep(-15, -14.4, -std::abs(s)) * smoothstep(3, 3.6, t) * smoothstep(-33, -32.4, -t);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
          double dx = s - (i - 1) * 10.0, dy = t - (-8.0 - 7.0 * j);
          double q = 1 - (dx * dx + dy * dy) / (2.8 * 2.8);
          if (q > 0) d += 1.0 * std::sqrt(q);
        }
      return d;
    }
    if (face == 5) {  // -z: s along y, t along x
      double dy = s - 28, dx = t - 9;
      return 1.0 * smoothstep(-4.2, -3.6, -std::sqrt(dx * dx + dy * dy));
    }
    return 0.0;
  });
  return m;
}

Mesh knight() {  // chess knight: turned base, tilted neck with a ridged mane, head, ears
  Mesh m;
  add_revolution(m,
                 {{0, 0, 0},
                  {17, 0, 10},
                  {17, 4, 4},
                  {15, 5.5, 2},
                  {15, 7.5, 2},
                  {13, 9, 2},
                  {11.5, 12, 3},
                  {12.5, 14, 2},
                  {10, 17, 3},
                  {9, 21, 3},
                  {0, 21, 6}},
                 120, false, {});
  add_box(
      m, {1, 0, 31}, {6.5, 6, 13}, 0.6,
      [](int face, double s, double t) {
        if (face != 1) return 0.0;  // -x face: the mane; s along z, t along y
        return 0.9 * std::pow(std::abs(std::sin(1.3 * s)), 2) * smoothstep(-5.5, -3.5, -std::abs(t)) *
               smoothstep(-12.5, -10.5, -std::abs(s));
      },
      rot_y(-14));
  // The head points along +x and tilts down towards the snout; eyes are dimples on its sides.
  add_box(
      m, {9, 0, 43}, {12, 5.5, 5}, 0.6,
      [](int face, double s, double t) {
        if (face != 2 && face != 3) return 0.0;
        double x = face == 2 ? t : s, z = face == 2 ? s : t;  // +y: s=z, t=x; -y: s=x, t=z
        double q = 1 - ((x + 4) * (x + 4) + (z - 1.5) * (z - 1.5)) / 2.25;
        return q > 0 ? -0.8 * std::sqrt(q) : 0.0;
      },
      rot_y(22));
  for (double y : {-3.0, 3.0}) add_revolution(m, {{0, 0, 0}, {2.2, 0, 3}, {0, 6, 6}}, 24, false, {-2, y, 48});
  return m;
}

Mesh mug() {  // a mug with a cavity and a ring handle
  Mesh m;
  add_revolution(m, {{0, 0, 0}, {30, 0, 10}, {30, 70, 60}, {27, 70, 3}, {27, 5, 50}, {0, 5, 10}}, 144, false, {});
  add_torus(m, {37, 0, 36}, {1, 0, 0}, {0, 0, 1}, 15, 4, 72, 16);
  return m;
}

Mesh die() {  // an 18 mm die with dimpled pips 1..6
  Mesh m;
  const double pip = 4.8;
  auto layout = [&](int face) -> std::vector<dvec2> {
    const dvec2 c(0, 0), tl(-pip, pip), tr(pip, pip), bl(-pip, -pip), br(pip, -pip), ml(-pip, 0), mr(pip, 0);
    switch (face) {
      case 4:
        return {c};
      case 0:
        return {tl, br};
      case 2:
        return {tl, c, br};
      case 3:
        return {tl, tr, bl, br};
      case 1:
        return {tl, tr, c, bl, br};
      default:
        return {tl, tr, ml, mr, bl, br};
    }
  };
  add_box(m, {}, {9, 9, 9}, 0.3, [&](int face, double s, double t) {
    double d = 0;
    for (dvec2 p : layout(face)) {
      double q = 1 - ((s - p.x) * (s - p.x) + (t - p.y) * (t - p.y)) / (1.9 * 1.9);
      if (q > 0) d -= 0.9 * std::sqrt(q);
    }
    return d;
  });
  return m;
}

Mesh bottle() {  // a bottle with grip rings and a ribbed cap
  Mesh m;
  add_revolution(m,
                 {{0, 0, 0},
                  {18, 0, 10},
                  {18, 2, 2},
                  {18, 60, 60},
                  {15, 70, 8},
                  {8, 80, 8},
                  {8, 84, 3},
                  {9.5, 84, 2},
                  {9.5, 96, 16},
                  {8.5, 98, 2},
                  {0, 98, 6}},
                 160, false, {}, [](double th, double r, double z) {
                   if (z > 84.2 && z < 95.8 && r > 9.4) return -0.5 * (0.5 + 0.5 * std::cos(40 * th));
                   if (z > 8 && z < 26 && r > 17.9)
                     return -0.8 * smoothstep(0.3, 0.5, fract(z / 3.0)) * smoothstep(-0.9, -0.7, -fract(z / 3.0));
                   return 0.0;
                 });
  return m;
}

Mesh brick() {  // a 2 x 4 building brick with studs
  Mesh m;
  add_box(m, {0, 0, 4.8}, {16, 8, 4.8}, 1.0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j)
      add_revolution(m, {{0, 0, 0}, {2.4, 0, 3}, {2.4, 2.2, 3}, {2.1, 2.5, 1}, {0, 2.5, 3}}, 40, false,
                     {-12.0 + 8 * i, -4.0 + 8 * j, 9.1});
  return m;
}

Mesh knob() {  // a knurled knob with a plain stem
  Mesh m;
  add_revolution(m,
                 {{0, 0, 0}, {20, 0, 10}, {20, 18, 45}, {17, 20, 4}, {6, 20, 10}, {6, 32, 12}, {5, 33, 2}, {0, 33, 5}},
                 288, false, {}, [](double th, double r, double z) {
                   if (z < 1 || z > 17 || r < 19.9) return 0.0;
                   double a = fract(36 * th / (2 * kPi) + z / 4), b = fract(36 * th / (2 * kPi) - z / 4);
                   return -0.7 * (1 - std::min(std::abs(2 * a - 1), std::abs(2 * b - 1)));
                 });
  return m;
}

// ---- raised letters: a 28 mm tile (top at z = 0) with the letter 3 mm high ----

struct Stroke {  // a rectangle from a to b with half width w, or a ring arc
  dvec2 a, b;
  double w;
  bool ring = false;
  double radius = 0, from = 0, to = 0;  // ring: centre a, angles in radians
};

double sd_segment(dvec2 p, const Stroke& s) {
  if (s.ring) {
    dvec2 d = p - s.a;
    double ang = std::atan2(d.y, d.x);
    bool inside = s.to - s.from >= 2 * kPi - 1e-9 || (ang >= s.from && ang <= s.to) ||
                  (ang + 2 * kPi >= s.from && ang + 2 * kPi <= s.to);
    if (inside) return std::abs(glm::length(d) - s.radius) - s.w;
    dvec2 e1 = s.a + s.radius * dvec2(std::cos(s.from), std::sin(s.from)),
          e2 = s.a + s.radius * dvec2(std::cos(s.to), std::sin(s.to));
    return std::min(glm::length(p - e1), glm::length(p - e2)) - s.w;
  }
  // Oriented box around the segment (square ends).
  dvec2 ax = s.b - s.a;
  double len = glm::length(ax);
  dvec2 u = ax / len, n(-u.y, u.x), q = p - 0.5 * (s.a + s.b);
  double x = std::abs(glm::dot(q, u)) - 0.5 * len, y = std::abs(glm::dot(q, n)) - s.w;
  return std::max(x, y) > 0 ? glm::length(glm::max(dvec2(x, y), dvec2(0.0))) : std::max(x, y);
}

Mesh letter(const std::vector<Stroke>& strokes) {
  Mesh m;
  const double half = 14, cell = 0.25, bottom = -1.0, height = 3.0;
  auto h = [&](double x, double y) {
    double d = 1e9;
    for (const auto& s : strokes) d = std::min(d, sd_segment({x, y}, s));
    return height * smoothstep(0.15, -0.15, d);
  };
  const int n = static_cast<int>(std::lround(2 * half / cell));
  add_grid(m, n, n, false, false, [&](double u, double v) {
    double x = (u - 0.5) * 2 * half, y = (v - 0.5) * 2 * half;
    return dvec3(x, y, h(x, y));
  });
  // Side walls follow the top's border; the bottom is one quad.
  auto wall = [&](dvec2 from, dvec2 to) {
    add_grid(m, n, 1, false, false, [&](double u, double v) {
      dvec2 p = from + u * (to - from);
      return dvec3(p.x, p.y, v < 0.5 ? bottom : h(p.x, p.y));
    });
  };
  wall({-half, -half}, {half, -half});
  wall({half, -half}, {half, half});
  wall({half, half}, {-half, half});
  wall({-half, half}, {-half, -half});
  add_grid(m, 1, 1, false, false,
           [&](double u, double v) { return dvec3((u - 0.5) * 2 * half, (0.5 - v) * 2 * half, bottom); });
  return m;
}

const double W = 2.25;  // half stroke width
Mesh letter_A() {
  return letter({{{-9.5, -12.5}, {0, 12.5}, W}, {{9.5, -12.5}, {0, 12.5}, W}, {{-5, -3.5}, {5, -3.5}, W}});
}
Mesh letter_E() {
  return letter({{{-7, -12.5}, {-7, 12.5}, W},
                 {{-9.25, 10.25}, {8.5, 10.25}, W},
                 {{-9.25, 0}, {6, 0}, W},
                 {{-9.25, -10.25}, {8.5, -10.25}, W}});
}
Mesh letter_I() {
  return letter({{{0, -12.5}, {0, 12.5}, W}, {{-7, 10.25}, {7, 10.25}, W}, {{-7, -10.25}, {7, -10.25}, W}});
}
Mesh letter_O() {
  Stroke ring{{0, 0}, {0, 0}, W, true, 10.25, -kPi, kPi};
  return letter({ring});
}
Mesh letter_U() {
  Stroke bowl{{0, -3}, {0, 0}, W, true, 7.25, -kPi, 0};
  return letter({{{-7.25, -3}, {-7.25, 12.5}, W}, {{7.25, -3}, {7.25, 12.5}, W}, bowl});
}

}  // namespace

std::vector<ObjectSpec> paper_objects() {
  return {{"glass", glass},       {"tyre", tyre},         {"screwdriver", screwdriver},
          {"phone", phone},       {"knight", knight},     {"mug", mug},
          {"die", die},           {"bottle", bottle},     {"brick", brick},
          {"knob", knob},         {"letter_A", letter_A}, {"letter_E", letter_E},
          {"letter_I", letter_I}, {"letter_O", letter_O}, {"letter_U", letter_U}};
}

}  // namespace sva::assets
