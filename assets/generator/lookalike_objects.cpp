// The look-alike families: near-twins that a touch sensor confuses, at their
// real sizes (40 to 250 mm), so that recognition can be measured where it is
// hardest. Each family's members differ by one thing that a 12 mm touch could
// in principle feel somewhere on the surface, and by nothing else:
//   1. one shape at several scales (clamps, cups, balls, boxes, spanners);
//   2. one size with a different local detail (seams, studs, tips, rims, edges);
//   3. mirror images (a chiral bracket and scissors, with a third variant);
//   4. one region that differs far from where most touches land (caps,
//      handles, the end of a rod).
// The declared symmetry is exact, as in the household set: where a real object
// would have a flip the scene format cannot state, a feature breaks it (a pin
// head, a valve, a logo, a lid, a boss); a mirror pair's members have no mirror
// plane, or a mirror image would be the same object turned round.
#include <algorithm>
#include <cmath>

#include "objects.hpp"

namespace sva::assets {

namespace {

// Scales the whole mesh about the origin by `factor`.
void scale(Mesh& m, double factor) { place(m, {}, glm::dmat3(factor), {}); }

// Scales the whole mesh about the origin so that its largest dimension is `size` mm.
void scale_to(Mesh& m, double size) {
  m.update_bounds();
  const dvec3 e = m.extent();
  scale(m, size / std::max({e.x, e.y, e.z}));
}

// A closed sphere-like shell about `c` whose radius in the unit direction d is
// radius(d): a latitude-longitude grid, nu cells round and nv from the bottom
// pole to the top one.
void add_sphere(Mesh& m, dvec3 c, int nu, int nv, const std::function<double(dvec3)>& radius) {
  add_grid(m, nu, nv, true, false, [&](double u, double v) {
    const double th = 2 * kPi * u, ph = kPi * v;
    const dvec3 d(std::sin(ph) * std::cos(th), std::sin(ph) * std::sin(th), -std::cos(ph));
    return c + radius(d) * d;
  });
}

// ---- 1. one shape at several scales -------------------------------------------

// A spring clamp, scaled to `size` mm long: two arms hinged on a barrel, the
// jaws closed on swivel pads at the front, the handles spread at the back in
// grip sleeves. The lower arm is the upper one mirrored; the two mirror planes
// would make a half turn about the clamp's length, which the pivot pin's head
// on one side breaks.
Mesh spring_clamp(double size) {
  Mesh m;
  auto height = [](double x) { return x >= 0 ? 12 - 8 * (x / 74) * (x / 74) : 12 + 26 * std::pow(-x / 96, 1.6); };
  for (double side : {1.0, -1.0}) {
    auto arm = mark(m);
    Sweep s;
    s.path = [&](double t) { return dvec3(74 - 170 * t, 0.0, height(74 - 170 * t)); };
    s.up = {0, 1, 0};
    s.radius = [](double) { return 3.0; };
    s.flatten = 3;  // 6 mm thick, 18 mm wide
    add_sweep(m, s);
    Sweep grip = s;
    grip.path = [&](double t) { return dvec3(-40 - 58 * t, 0.0, height(-40 - 58 * t)); };
    grip.radius = [](double) { return 5.5; };
    grip.flatten = 2;
    grip.n_t = 16;
    add_sweep(m, grip);
    auto pad = mark(m);
    add_rounded_box(m, {7, 9, 2.2}, 1.5, 4);
    place(m, pad, glm::dmat3(1.0), {70, 0, 2});
    place(m, arm, glm::dmat3(dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, side)), {});
  }
  auto pivot = mark(m);
  add_revolution(m, {{0, -11, 0}, {9.5, -11, 3}, {9.5, 11, 8}, {0, 11, 3}}, 32, false, {});
  add_revolution(m, {{0, 0, 0}, {5.5, 0, 2}, {5.5, 1.5, 1}, {4.5, 2.5, 1}, {0, 2.5, 2}}, 24, false, {0, 0, 10.5});
  place(m, pivot, rot_x(-90), {});  // the barrel's axis along y, the pin head on +y
  scale_to(m, size);
  return m;
}
Mesh spring_clamp_89() { return spring_clamp(89); }
Mesh spring_clamp_120() { return spring_clamp(120); }
Mesh spring_clamp_171() { return spring_clamp(171); }

// A stacking cup of a nested set, scaled to `height` mm tall (its largest
// dimension): a foot ring, a tapered wall and a bead round the rim. Open at the
// top and closed below, it has no flip: an axis.
Mesh nested_cup(double height) {
  Mesh m;
  add_revolution(
      m,
      vessel({{0, 2, 0}, {24, 2, 5}, {25, 0, 1}, {28, 0, 2}, {29, 3, 2}, {39.5, 90, 20}, {41.5, 92, 2}, {41.5, 98, 3}},
             2.5, 5),
      72, false, {});
  scale_to(m, height);
  return m;
}
Mesh nested_cup_74() { return nested_cup(74); }
Mesh nested_cup_80() { return nested_cup(80); }
Mesh nested_cup_86() { return nested_cup(86); }
Mesh nested_cup_92() { return nested_cup(92); }
Mesh nested_cup_98() { return nested_cup(98); }

// A smooth rubber ball `diameter` mm across with its valve plug at the top
// pole (the plug leaves the axis through it as the only symmetry of the
// sphere); the plug scales with the ball, so the balls are one shape.
Mesh ball(double diameter) {
  Mesh m;
  add_sphere(m, {}, 96, 48, [](dvec3) { return 35.0; });
  add_revolution(m, {{0, 0, 0}, {3.5, 0, 2}, {3.5, 2.3, 2}, {3, 2.8, 1}, {0, 2.8, 2}}, 24, false, {0, 0, 33});
  scale(m, diameter / 70);
  return m;
}
Mesh ball_64() { return ball(64); }
Mesh ball_70() { return ball(70); }
Mesh ball_74() { return ball(74); }

// A gift box of one aspect ratio, scaled to `size` mm long: a rounded box with
// a lid standing out round its top, which breaks the box's flips and leaves
// the half turn about z.
Mesh gift_box(double size) {
  Mesh m;
  add_rounded_box(m, {90, 55, 33}, 3, 12);
  auto lid = mark(m);
  add_rounded_box(m, {91.5, 56.5, 10}, 3, 12);
  place(m, lid, glm::dmat3(1.0), {0, 0, 25});
  scale_to(m, size);
  return m;
}
Mesh gift_box_80() { return gift_box(80); }
Mesh gift_box_120() { return gift_box(120); }
Mesh gift_box_180() { return gift_box(180); }

// An open jaw of a spanner: a round head of radius r with a slot w mm across
// cut into it along +x.
std::vector<dvec2> jaw_outline(double r, double w) {
  std::vector<dvec2> jaw;
  const double a = std::asin(w / 2 / r) * 180 / kPi;
  append_arc(jaw, {0, 0}, r, a, 360 - a, 40);
  jaw.insert(jaw.end(), {{-w / 4, -w / 2}, {-w / 4, w / 2}});
  return jaw;
}

// A flat double open-end spanner (jaws of 13 and 10 mm when 187 mm long),
// scaled to `size` mm long: both heads turned 15 degrees the same way and of
// different sizes, so that its only symmetry is the mirror through its thickness.
Mesh open_wrench(double size) {
  Mesh m;
  std::vector<dvec2> handle;
  append_arc(handle, {-62, 0}, 7, 90, 270, 8);
  append_arc(handle, {62, 0}, 8, -90, 90, 8);
  add_extrusion(m, handle, -2.5, 2.5);
  auto big = mark(m);
  add_extrusion(m, jaw_outline(16, 13), -3.5, 3.5);
  place(m, big, rot_z(15), {80, 0, 0});
  auto small = mark(m);
  add_extrusion(m, jaw_outline(13, 10), -3.5, 3.5);
  place(m, small, rot_z(195), {-78, 0, 0});
  scale_to(m, size);
  return m;
}
Mesh open_wrench_130() { return open_wrench(130); }
Mesh open_wrench_165() { return open_wrench(165); }
Mesh open_wrench_210() { return open_wrench(210); }

// ---- 2. one size, a different local detail --------------------------------------

// The seam of a tennis ball or a baseball, n points: the closed curve that
// cuts the unit sphere into two congruent halves (a + b = 1). Its rotations
// are the half turns about x, y and z; it keeps 29 degrees clear of the poles.
std::vector<dvec3> seam_curve(int n) {
  const double a = 0.74, b = 0.26;
  std::vector<dvec3> out;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n;
    out.push_back({a * std::cos(t) + b * std::cos(3 * t), a * std::sin(t) - b * std::sin(3 * t),
                   2 * std::sqrt(a * b) * std::sin(2 * t)});
  }
  return out;
}

enum class Seam { none, ridge, groove };

// A 67 mm ball (a tennis ball's size) with a round raised logo at the top pole
// and a seam: none, a raised ridge (a baseball's stitching) or a groove (a
// tennis ball's). The logo sits on the seam's half turn about z, so a ball
// with a seam keeps that half turn only, and the plain ball its axis.
Mesh seam_ball(Seam seam) {
  const double R = 33.5;
  const std::vector<dvec3> path = seam_curve(720);
  Mesh m;
  add_sphere(m, {}, 120, 66, [&](dvec3 d) {
    const double logo = 0.8 * (1 - smoothstep(5, 6.5, R * glm::length(d - dvec3(0, 0, 1))));
    if (seam == Seam::none) return R + logo;
    double near = 4;  // squared chord to the nearest point of the seam
    for (const dvec3& q : path) near = std::min(near, glm::dot(d - q, d - q));
    const double bump = 1 - smoothstep(1.0, 2.5, R * std::sqrt(near));
    return R + logo + (seam == Seam::ridge ? 1.2 : -1.0) * bump;
  });
  return m;
}
Mesh seam_ball_smooth() { return seam_ball(Seam::none); }
Mesh seam_ball_ridge() { return seam_ball(Seam::ridge); }
Mesh seam_ball_groove() { return seam_ball(Seam::groove); }

// A jumbo building brick of 2 x n studs on a 21 mm pitch: 24 mm tall with
// 12.6 mm studs for every n. The closed flat underside keeps the studs on one
// face: 4-fold for 2 x 2, else 2-fold.
Mesh stud_brick(int n) {
  Mesh m;
  const double pitch = 21;
  add_rounded_box(m, {n * pitch / 2, pitch, 12}, 1.2, 8);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2; ++j)
      add_revolution(m, {{0, 0, 0}, {6.3, 0, 3}, {6.3, 5.5, 3}, {5.8, 6, 1}, {0, 6, 3}}, 32, false,
                     {(i - (n - 1) / 2.0) * pitch, (j - 0.5) * pitch, 11.5});
  return m;
}
Mesh brick_2x2() { return stud_brick(2); }
Mesh brick_2x3() { return stud_brick(3); }
Mesh brick_2x4() { return stud_brick(4); }

enum class Tip { flat, cross, hex, torx };

// The radius of a screwdriver tip's section at angle th where the tip is
// narrower than the round shaft of radius r.
double tip_section(Tip tip, double th, double r) {
  switch (tip) {
    case Tip::flat: {  // a blade 1.4 mm thick
      const double c = std::abs(std::cos(th));
      return c > 1e-6 ? 0.7 / c : 1e9;
    }
    case Tip::cross:  // four flutes
      return r * (1 - 0.45 * smoothstep(0.6, 0.9, std::cos(4 * th)));
    case Tip::hex:  // 6 mm across the flats
      return 3.0 / std::cos(std::fmod(th, kPi / 3) - kPi / 6);
    case Tip::torx:  // six round lobes
      return 2.9 + 0.6 * std::cos(6 * th);
  }
  return r;
}

// A 170 mm screwdriver with the same fluted handle and 8 mm shaft for every
// tip; only the last 12 mm differ. The 12 flutes' symmetry contains the tip's,
// so the driver has the tip's: a flat blade 2-fold, a cross 4-fold, a hex or
// a torx 6-fold.
Mesh tip_driver(Tip tip) {
  Mesh m;
  const double hr = 15, hl = 95, sr = 4, z1 = hl + 75;
  Profile p{{0, 0, 0},           {hr - 3, 0, 4},  {hr, 3, 2},      {hr, hl - 15, 20},
            {hr - 5, hl - 4, 4}, {sr + 3, hl, 3}, {sr, hl + 2, 2}, {sr, z1 - 12, 14}};
  if (tip == Tip::cross)
    p.insert(p.end(), {{sr, z1 - 9, 3}, {0.8, z1, 9}, {0, z1, 1}});  // a pointed cone
  else
    p.insert(p.end(), {{sr, z1 - 1, 11}, {sr - 0.8, z1, 1}, {0, z1, 4}});  // a chamfered end
  // Where the tip's section takes over from the round shaft: a flat blade as a
  // wedge, a cross as the household Phillips driver, a hex or torx bit at a shoulder.
  const double from = tip == Tip::cross ? 10 : 12, to = tip == Tip::flat ? 5 : tip == Tip::cross ? 6 : 11;
  add_revolution(m, p, 72, false, {}, [=](double th, double r, double z) {
    if (z > 4 && z < hl - 16 && r > hr - 0.1) return -2.0 * smoothstep(0.5, 0.85, std::cos(12 * th));
    if (z < z1 - 12) return 0.0;
    const double w = smoothstep(z1 - from, z1 - to, z);
    return (std::min(r, tip_section(tip, th, r)) - r) * w;
  });
  return m;
}
Mesh driver_flat() { return tip_driver(Tip::flat); }
Mesh driver_cross() { return tip_driver(Tip::cross); }
Mesh driver_hex() { return tip_driver(Tip::hex); }
Mesh driver_torx() { return tip_driver(Tip::torx); }

// A 200 mm plate on one foot ring: `top` continues the profile from the
// foot's outer edge round the rim and back over the well to the axis. The foot
// below and the well above leave the axis only.
Mesh plate(const Profile& top) {
  Mesh m;
  Profile p{{0, 2, 0}, {44, 2, 8}, {46, 0, 1}, {52, 0, 2}, {54, 2, 1}};
  p.insert(p.end(), top.begin(), top.end());
  add_revolution(m, p, 96, false, {});
  return m;
}
Mesh plate_no_rim() {  // flat to a rounded edge
  return plate({{96, 3, 8}, {100, 5, 2}, {99.5, 7, 1}, {97, 7.5, 1}, {0, 7.5, 18}});
}
Mesh plate_rim() {  // a narrow rim turned up steeply round a wide well
  return plate({{80, 4, 5},
                {96, 17, 5},
                {100, 21, 2},
                {99, 22.5, 1},
                {97, 22, 1},
                {93, 17.5, 3},
                {77, 7, 5},
                {72, 6, 1},
                {0, 6, 14}});
}
Mesh plate_wide_rim() {  // a wide sloping rim round a smaller well
  return plate({{66, 4, 2}, {98, 16, 8}, {100, 19, 1}, {98, 20, 1}, {64, 8, 8}, {60, 6, 2}, {0, 6, 12}});
}

// A 55 mm cube whose edges are rounded with radius r, with a round boss on its
// top face that leaves the 4-fold turn about z of the cube's symmetries.
Mesh rounded_cube(double r, int round_segments) {
  Mesh m;
  add_rounded_box(m, {27.5, 27.5, 27.5}, r, 8, round_segments);
  add_revolution(m, {{0, 0, 0}, {7, 0, 3}, {7, 2, 1}, {0, 2, 3}}, 32, false, {0, 0, 27});
  return m;
}
Mesh cube_r2() { return rounded_cube(2, 3); }
Mesh cube_r6() { return rounded_cube(6, 4); }
Mesh cube_r12() { return rounded_cube(12, 6); }

// ---- 3. mirror images ---------------------------------------------------------

// Mirrors the whole mesh in the plane through `point` normal to the axis
// (0: x, 1: y, 2: z); `place` turns the triangles round to keep them facing out.
Mesh mirrored(Mesh m, int axis, double point) {
  glm::dmat3 flip(1.0);
  flip[axis][axis] = -1;
  dvec3 offset(0.0);
  offset[axis] = 2 * point;
  place(m, {}, flip, offset);
  return m;
}

// An angle bracket of 5 mm plate, legs of 80 (x) and 60 mm (z), 40 mm wide
// (y), with a triangular gusset 4 mm thick across its corner from y = g.
// Unequal legs leave the L no mirror but the plane y = 20; a gusset at one
// side breaks that too, so that bracket is chiral (one in the middle keeps it).
Mesh angle_bracket(double g) {
  Mesh m;
  add_extrusion(m, {{0, 0}, {80, 0}, {80, 5}, {5, 5}, {5, 60}, {0, 60}}, -40, 0, 4);
  add_extrusion(m, {{2, 2}, {35, 2}, {2, 35}}, -g - 4, -g);
  place(m, {}, rot_x(90), {});  // the outline's y to z, its depth to y in [0, 40]
  return m;
}
Mesh bracket_left() { return angle_bracket(0); }
Mesh bracket_right() { return mirrored(bracket_left(), 1, 20); }
Mesh bracket_middle() { return angle_bracket(18); }

// One blade of a pair of scissors in the layer z0..z1: its cutting edge along
// y = -2 side from behind the pivot to the tip, its back up to 12 mm from the
// edge on the `side` of it (+1: +y); a blunt blade ends in a round nose.
void add_blade(Mesh& m, double side, double z0, double z1, bool blunt) {
  const double tip = blunt ? 92 : 100;
  auto width = [=](double x) {
    const double f = std::pow(std::max(0.0, 1 - x / tip), 0.8);
    return blunt ? 6 + 6 * f : 12 * f;
  };
  std::vector<dvec2> o{{-10, -2}};
  if (blunt)
    append_arc(o, {tip, 1}, 3, -90, 90, 8);
  else
    o.push_back({tip, -2});
  for (int k = 1; k <= 16; ++k) {  // the back, from the tip to behind the pivot
    const double x = tip - (tip + 10) * k / 16.0;
    o.push_back({x, -2 + width(std::max(0.0, x))});
  }
  for (dvec2& q : o) q.y *= side;
  add_extrusion(m, o, z0, z1, 1);
}

// A scissor half's shank in the plane z, from the pivot to its finger ring.
void add_shank(Mesh& m, dvec2 from, dvec2 to, double z) {
  Sweep s;
  s.path = [=](double t) { return dvec3(from + t * (to - from), z); };
  s.radius = [](double) { return 4.0; };
  s.flatten = 0.6;
  s.n_t = 8;
  s.n_phi = 12;
  add_sweep(m, s);
}

// Right-handed scissors, 181 mm: two blades in two layers (the one on the +y
// side below), crossed shanks, a round thumb ring and a long finger ring. The
// rings differ, so nothing turns the scissors into themselves; the layers'
// order makes them chiral (left-handed scissors are their mirror image).
Mesh scissors(bool blunt) {
  Mesh m;
  add_blade(m, 1, -2.6, 0.1, blunt);
  add_blade(m, -1, -0.1, 2.6, blunt);
  add_shank(m, {-4, 2}, {-44, -14}, -1.25);
  add_shank(m, {-4, -2}, {-44, 14}, 1.25);
  add_torus(m, {-55, -18, -1.25}, {1, 0, 0}, {0, 1, 0}, 10, 3.5, 40, 12);  // the thumb ring
  auto ring = mark(m);
  add_torus(m, {}, {1, 0, 0}, {0, 1, 0}, 11, 3.5, 48, 12);
  place(m, ring, glm::dmat3(dvec3(1.6, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)), {-58, 20, 1.25});
  add_revolution(m, {{0, -3.6, 0}, {4, -3.6, 2}, {4, 3.6, 3}, {0, 3.6, 2}}, 24, false, {});  // the pivot screw
  return m;
}
Mesh scissors_right() { return scissors(false); }
Mesh scissors_left() { return mirrored(scissors_right(), 2, 0); }
Mesh scissors_blunt() { return scissors(true); }

// ---- 4. one region differs --------------------------------------------------------

enum class Cap { flat, ribbed, sport, flip };

// A 66 mm bottle with the same plain body, shoulder, neck and support ring
// under four caps: a smooth flat one, the same with 24 ribs (24-fold), a
// push-pull sports cap, and the flat one with a flip lid's hinge and thumb tab
// (no symmetry). The base keeps every cap's axis free of a flip.
Mesh capped_bottle(Cap cap) {
  Mesh m;
  Profile p{{0, 4, 0}, {25, 1, 6}, {30, 0, 2}, {33, 3, 2}, {33, 150, 16}};
  curve(p, 12, [](double s) { return dvec2(33 - 19.5 * std::sin(s * kPi / 2), 150 + 40 * s); });
  p.insert(p.end(), {{13.5, 192, 1}, {17, 192, 2}, {17, 195, 2}, {13.5, 195, 2}, {13.5, 212, 6}, {0, 212, 5}});
  add_revolution(m, p, 72, false, {});  // 72 = 3 x 24: the body keeps the ribbed cap's symmetry
  if (cap == Cap::sport) {
    add_revolution(m,
                   {{0, 197, 0},
                    {16, 197, 3},
                    {16, 209, 6},
                    {15, 210, 1},
                    {9, 210, 2},
                    {9, 216, 3},
                    {6.5, 217, 1},
                    {6.5, 225, 4},
                    {5.5, 226.5, 1},
                    {2.5, 226.5, 1},
                    {2.5, 224, 1},
                    {0, 224, 1}},
                   96, false, {});
    return m;
  }
  add_revolution(m, {{0, 197, 0}, {16, 197, 3}, {16, 217, 10}, {15, 218, 1}, {0, 218, 4}}, 96, false, {},
                 [cap](double th, double r, double z) {
                   if (cap != Cap::ribbed || z < 197.5 || z > 216.5 || r < 15.9) return 0.0;
                   return -0.8 * smoothstep(0.2, 0.8, std::cos(24 * th));
                 });
  if (cap == Cap::flip) {
    auto hinge = mark(m);
    add_rounded_box(m, {2.5, 7, 3}, 1, 4);
    place(m, hinge, glm::dmat3(1.0), {-16.5, 0, 209});
    auto tab = mark(m);
    add_rounded_box(m, {3.5, 6, 2}, 1, 4);
    place(m, tab, glm::dmat3(1.0), {17.5, 0, 215});
  }
  return m;
}
Mesh bottle_flat_cap() { return capped_bottle(Cap::flat); }
Mesh bottle_ribbed_cap() { return capped_bottle(Cap::ribbed); }
Mesh bottle_sport_cap() { return capped_bottle(Cap::sport); }
Mesh bottle_flip_cap() { return capped_bottle(Cap::flip); }

enum class Handle { d, loop, square };

// A barrel-shaped mug, 90 mm tall and 82 mm across at its widest, with one of
// three handles in the xz plane: a flat D, a round loop, or a square one of
// three bars. The handle leaves only the mirror y = 0: no symmetry.
Mesh handled_mug(Handle handle) {
  Mesh m;
  Profile out{{0, 0, 0}, {33, 0, 6}, {35, 2, 2}, {36, 4, 1}};
  curve(out, 12, [](double s) { return dvec2(36 + 5 * std::sin(kPi * s), 4 + 86 * s); });
  add_revolution(m, vessel(out, 3.5, 7), 72, false, {});
  if (handle == Handle::d) add_handle(m, {38, 0, 74}, {38, 0, 22}, 28, 4.5, 1.6);
  if (handle == Handle::loop) add_handle(m, {38, 0, 70}, {38, 0, 30}, 24, 5.5, 1.0);
  if (handle == Handle::square)
    for (const auto& [half, centre] :
         {std::pair{dvec3(12, 6, 4), dvec3(50, 0, 70)}, std::pair{dvec3(4, 6, 22), dvec3(58, 0, 48)},
          std::pair{dvec3(12, 6, 4), dvec3(50, 0, 26)}}) {
      auto bar = mark(m);
      add_rounded_box(m, half, 3, 6);
      place(m, bar, glm::dmat3(1.0), centre);
    }
  return m;
}
Mesh mug_d_handle() { return handled_mug(Handle::d); }
Mesh mug_loop_handle() { return handled_mug(Handle::loop); }
Mesh mug_square_handle() { return handled_mug(Handle::square); }

enum class End { flat, dome, point, ferrule };

// A 200 mm dowel handle, 20 mm across, with a 30 mm ball knob at the bottom and
// one of four tops from z = 180: cut flat, a dome, a point, or flat with a
// metal ferrule round it. The knob differs from every top: an axis, no flip.
Mesh dowel(End end) {
  Mesh m;
  Profile p{{0, 0, 0}};
  curve(p, 14, [](double s) {
    const double a = -kPi / 2 + s * (kPi / 2 + std::acos(10.0 / 15));
    return dvec2(15 * std::cos(a), 15 + 15 * std::sin(a));
  });
  p.insert(p.end(), {{9, 29, 2}, {10, 32, 2}, {10, 180, 30}});
  if (end == End::flat) p.insert(p.end(), {{10, 199, 8}, {9, 200, 1}, {0, 200, 4}});
  if (end == End::dome) {
    p.push_back({10, 190, 4});
    curve(p, 8, [](double s) { return dvec2(10 * std::cos(s * kPi / 2), 190 + 10 * std::sin(s * kPi / 2)); });
    p.back().r = 0;
  }
  if (end == End::point) p.insert(p.end(), {{1, 200, 10}, {0, 200, 1}});
  if (end == End::ferrule)
    p.insert(p.end(),
             {{10, 181, 1}, {11.5, 182, 1}, {11.5, 197, 8}, {10, 198, 1}, {10, 199, 1}, {9, 200, 1}, {0, 200, 4}});
  add_revolution(m, p, 48, false, {});
  return m;
}
Mesh dowel_flat() { return dowel(End::flat); }
Mesh dowel_dome() { return dowel(End::dome); }
Mesh dowel_point() { return dowel(End::point); }
Mesh dowel_ferrule() { return dowel(End::ferrule); }

}  // namespace

std::vector<LookalikeFamily> lookalike_families() {
  const std::string none = "\"none\"", axis = axis_symmetry(), half_turn = cyclic_symmetry(2);
  return {
      // 1. one shape at several scales
      {"spring_clamps",
       {{"spring_clamp_89", spring_clamp_89, none},
        {"spring_clamp_120", spring_clamp_120, none},
        {"spring_clamp_171", spring_clamp_171, none}}},
      {"nested_cups",
       {{"nested_cup_74", nested_cup_74, axis},
        {"nested_cup_80", nested_cup_80, axis},
        {"nested_cup_86", nested_cup_86, axis},
        {"nested_cup_92", nested_cup_92, axis},
        {"nested_cup_98", nested_cup_98, axis}}},
      {"balls", {{"ball_64", ball_64, axis}, {"ball_70", ball_70, axis}, {"ball_74", ball_74, axis}}},
      {"gift_boxes",
       {{"gift_box_80", gift_box_80, half_turn},
        {"gift_box_120", gift_box_120, half_turn},
        {"gift_box_180", gift_box_180, half_turn}}},
      {"open_wrenches",
       {{"open_wrench_130", open_wrench_130, none},
        {"open_wrench_165", open_wrench_165, none},
        {"open_wrench_210", open_wrench_210, none}}},
      // 2. one size, a different local detail
      {"ball_seams",
       {{"seam_ball_smooth", seam_ball_smooth, axis},
        {"seam_ball_ridge", seam_ball_ridge, half_turn},
        {"seam_ball_groove", seam_ball_groove, half_turn}}},
      {"stud_bricks",
       {{"brick_2x2", brick_2x2, cyclic_symmetry(4)},
        {"brick_2x3", brick_2x3, half_turn},
        {"brick_2x4", brick_2x4, half_turn}}},
      {"screwdriver_tips",
       {{"driver_flat", driver_flat, half_turn},
        {"driver_cross", driver_cross, cyclic_symmetry(4)},
        {"driver_hex", driver_hex, cyclic_symmetry(6)},
        {"driver_torx", driver_torx, cyclic_symmetry(6)}}},
      {"plate_rims",
       {{"plate_no_rim", plate_no_rim, axis},
        {"plate_rim", plate_rim, axis},
        {"plate_wide_rim", plate_wide_rim, axis}}},
      {"cube_edges",
       {{"cube_r2", cube_r2, cyclic_symmetry(4)},
        {"cube_r6", cube_r6, cyclic_symmetry(4)},
        {"cube_r12", cube_r12, cyclic_symmetry(4)}}},
      // 3. mirror images
      {"angle_brackets",
       {{"bracket_left", bracket_left, none},
        {"bracket_right", bracket_right, none},
        {"bracket_middle", bracket_middle, none}}},
      {"scissors",
       {{"scissors_right", scissors_right, none},
        {"scissors_left", scissors_left, none},
        {"scissors_blunt", scissors_blunt, none}}},
      // 4. one region differs
      {"bottle_caps",
       {{"bottle_flat_cap", bottle_flat_cap, axis},
        {"bottle_ribbed_cap", bottle_ribbed_cap, cyclic_symmetry(24)},
        {"bottle_sport_cap", bottle_sport_cap, axis},
        {"bottle_flip_cap", bottle_flip_cap, none}}},
      {"mug_handles",
       {{"mug_d_handle", mug_d_handle, none},
        {"mug_loop_handle", mug_loop_handle, none},
        {"mug_square_handle", mug_square_handle, none}}},
      {"dowel_ends",
       {{"dowel_flat", dowel_flat, axis},
        {"dowel_dome", dowel_dome, axis},
        {"dowel_point", dowel_point, axis},
        {"dowel_ferrule", dowel_ferrule, axis}}},
  };
}

}  // namespace sva::assets
