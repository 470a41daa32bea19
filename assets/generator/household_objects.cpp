// The household set: 50 everyday objects at their real sizes (40 to 250 mm in
// their largest dimension), for recognition among many objects (sva issue 10).
// Each is a union of closed shells made by the shared helpers (lathe, rounded
// box, sweep, extrusion, torus). Where a real object's symmetry would include
// a flip that the scene format cannot state (it knows an axis of revolution or
// an n-fold rotation about one axis), a feature breaks the flip (a foot ring,
// a rim on one side, a knob on one face), so the declared symmetry is exact.
#include <algorithm>
#include <cmath>

#include "objects.hpp"

namespace sva::assets {

namespace {

// ---- cups, glasses and bottles --------------------------------------------

Mesh mug_straight() {  // a straight mug with a D handle
  Mesh m;
  add_revolution(m, vessel({{0, 0, 0}, {38, 0, 8}, {41, 3, 3}, {41, 96, 24}}, 3.5, 7), 72, false, {});
  add_handle(m, {40, 0, 80}, {40, 0, 22}, 28, 4.5, 1.6);
  return m;
}

Mesh mug_tapered() {  // a conical mug, wider at the top, with a round loop handle
  Mesh m;
  add_revolution(m, vessel({{0, 0, 0}, {31, 0, 8}, {34, 3, 3}, {46, 100, 24}}, 3.5, 7), 72, false, {});
  add_handle(m, {42.5, 0, 80}, {36.3, 0, 30}, 26, 5, 1.0);
  return m;
}

Mesh espresso_cup() {  // a small thick cup on a foot ring, with a small handle
  Mesh m;
  Profile out{{0, 2, 0}, {17, 2, 4}, {18, 0, 1}, {21, 0, 2}, {22, 3, 2}};
  curve(out, 10, [](double s) { return dvec2(22 + 6 * std::sin(s * kPi / 2), 3 + 50 * s); });
  add_revolution(m, vessel(out, 4, 9), 80, false, {});
  add_handle(m, {26.7, 0, 43}, {23.7, 0, 18}, 16, 3.5, 1.5);
  return m;
}

Mesh teacup() {  // a flared tea cup on a foot ring, with a loop handle
  Mesh m;
  Profile out{{0, 2, 0}, {20, 2, 4}, {21, 0, 1}, {25, 0, 2}, {26, 4, 2}};
  curve(out, 14, [](double s) { return dvec2(26 + 21 * std::pow(s, 0.7), 4 + 56 * s); });
  add_revolution(m, vessel(out, 3, 7), 96, false, {});
  add_handle(m, {42.5, 0, 48}, {32.5, 0, 18}, 22, 4, 1.2);
  return m;
}

Mesh wine_glass() {  // foot, thin stem and an egg-shaped bowl
  Mesh m;
  Profile out{{0, 0, 0}, {36, 0, 8}, {36, 3, 1}, {30, 5, 2}, {8, 12, 6}, {4, 20, 3}, {4, 82, 14}, {10, 90, 3}};
  curve(out, 18, [](double s) {
    double a = s * 0.55 * kPi;  // from the bottom of the bowl round to its mouth
    return dvec2(10 + 32 * std::sin(a) - 2 * s, 90 + 90 * (1 - std::cos(a)) * 0.6);
  });
  add_revolution(m, vessel(out, 2, 96), 72, false, {});
  return m;
}

Mesh water_bottle() {  // grip rings, a shoulder and a ribbed screw cap
  Mesh m;
  Profile p{{0, 0, 0}, {31, 0, 8}, {34, 3, 2}, {34, 56, 8}, {34, 124, 28}, {34, 150, 4}};
  curve(p, 12, [](double s) { return dvec2(34 - 20 * std::sin(s * kPi / 2), 150 + 48 * s); });
  p.insert(p.end(), {{14, 204, 3}, {16, 204, 1}, {16, 228, 10}, {14.5, 230, 1}, {0, 230, 4}});
  add_revolution(m, p, 96, false, {}, [](double th, double r, double z) {
    if (z > 204.5 && z < 227.5 && r > 15.9) return -0.8 * smoothstep(0.2, 0.8, std::cos(24 * th));      // cap ribs
    if (z > 60 && z < 120 && r > 33.9) return -1.5 * smoothstep(0.6, 0.9, std::cos(2 * kPi * z / 12));  // grips
    return 0.0;
  });
  return m;
}

Mesh wine_bottle() {  // tall body, rounded shoulder, long neck, lip ring, punt underneath
  Mesh m;
  Profile p{{0, 14, 0}, {20, 4, 6}, {30, 0, 3}, {36, 1, 2}, {37.5, 6, 2}, {37.5, 160, 20}};
  curve(p, 12, [](double s) { return dvec2(37.5 - 23.5 * std::pow(std::sin(s * kPi / 2), 2), 160 + 50 * s); });
  p.insert(p.end(), {{14, 236, 8}, {16, 238, 1}, {16, 248, 3}, {14, 250, 1}, {9, 250, 2}, {9, 245, 2}, {0, 245, 3}});
  add_revolution(m, p, 72, false, {});
  return m;
}

// ---- cans and jars ----------------------------------------------------------

Mesh soda_can() {  // domed bottom on a stand ring, necked top with a recessed lid
  Mesh m;
  add_revolution(m,
                 {{0, 12, 0},
                  {20, 4, 6},
                  {25, 0, 3},
                  {28, 0, 1},
                  {33, 8, 3},
                  {33, 108, 30},
                  {27, 118, 4},
                  {27.5, 122, 2},
                  {26, 122, 1},
                  {25, 118, 2},
                  {0, 118, 6}},
                 64, false, {});
  return m;
}

Mesh food_tin() {  // corrugated tin can: beaded walls, a rolled top seam, a narrower base
  Mesh m;
  add_revolution(m,
                 {{0, 1, 0},
                  {38, 1, 8},
                  {40, 0, 1},
                  {42, 4, 2},
                  {42, 106, 50},
                  {43, 107, 1},
                  {43, 110, 2},
                  {41, 110, 1},
                  {40.5, 107, 2},
                  {0, 107, 8}},
                 64, false, {}, [](double, double r, double z) {
                   if (r < 41.9 || z < 12 || z > 98) return 0.0;
                   return -1.6 * smoothstep(0.5, 0.9, std::cos(2 * kPi * (z - 12) / 14.3));
                 });
  return m;
}

Mesh jam_jar() {  // glass jar with a shoulder and a knurled twist lid
  Mesh m;
  Profile p{{0, 0, 0}, {32, 0, 8}, {35, 3, 2}, {35, 66, 10}};
  curve(p, 6, [](double s) { return dvec2(35 - 5 * std::sin(s * kPi / 2), 66 + 10 * s); });
  p.insert(p.end(), {{36, 78, 2}, {36, 98, 10}, {34, 100, 2}, {0, 100, 8}});
  add_revolution(m, p, 120, false, {}, [](double th, double r, double z) {
    if (z < 79 || z > 97 || r < 35.9) return 0.0;
    return -0.9 * smoothstep(0.3, 0.8, std::cos(30 * th));
  });
  return m;
}

Mesh spray_can() {  // can, domed shoulder, valve, actuator with a sideways nozzle
  Mesh m;
  Profile p{{0, 8, 0}, {22, 2, 6}, {29, 0, 2}, {32, 4, 2}, {32, 150, 20}};
  curve(p, 10, [](double s) { return dvec2(32 - 19 * std::sin(s * kPi / 2), 150 + 15 * std::sin(s * kPi / 2)); });
  p.insert(p.end(), {{13, 170, 2}, {11, 170, 1}, {11, 183, 4}, {9, 185, 1}, {0, 185, 3}});
  add_revolution(m, p, 80, false, {});
  auto nozzle = mark(m);
  add_revolution(m, {{0, 0, 0}, {3, 0, 1}, {3, 10, 3}, {1.5, 10, 1}, {1.5, 9, 1}, {0, 9, 1}}, 20, false, {});
  place(m, nozzle, rot_y(90), {7, 0, 178});
  return m;
}

// ---- bowls, plates, rings -------------------------------------------------

Mesh cereal_bowl() {  // a deep round bowl on a foot ring
  Mesh m;
  Profile out{{0, 2, 0}, {32, 2, 6}, {34, 0, 1}, {38, 0, 1}, {40, 4, 2}};
  curve(out, 16, [](double s) {
    double a = s * kPi / 2;
    return dvec2(40 + 40 * std::sin(a), 4 + 56 * (1 - std::cos(a)));
  });
  add_revolution(m, vessel(out, 4, 8), 80, false, {});
  return m;
}

Mesh mixing_bowl() {  // a wide mixing bowl with a rolled rim
  Mesh m;
  Profile out{{0, 0, 0}, {55, 0, 10}, {60, 2, 2}};
  curve(out, 18, [](double s) {
    double a = s * kPi / 2;
    return dvec2(60 + 52 * std::sin(a), 2 + 100 * (1 - std::cos(a)));
  });
  add_revolution(m, vessel(out, 3, 3), 96, false, {});
  add_torus(m, {0, 0, 102}, {1, 0, 0}, {0, 1, 0}, 111, 5, 96, 10);  // the rolled rim
  return m;
}

Mesh dinner_plate() {  // flat well, sloped rim, foot ring underneath
  Mesh m;
  add_revolution(m,
                 {{0, 2, 0},
                  {56, 2, 10},
                  {58, 0, 1},
                  {64, 0, 2},
                  {66, 2, 1},
                  {85, 6, 4},
                  {124, 18, 8},
                  {125, 21, 1},
                  {123, 22, 1},
                  {82, 10, 8},
                  {78, 6, 2},
                  {0, 6, 12}},
                 96, false, {});
  return m;
}

Mesh tape_roll() {  // a roll of tape on a cardboard core that stands out on one side
  Mesh m;
  add_revolution(m, {{38, 0, 0}, {50, 0, 4}, {50, 46, 10}, {41, 46, 3}, {41, 50, 1}, {38, 50, 1}, {38, 0, 10}}, 120,
                 true, {});
  return m;
}

Mesh ring_toss() {  // a ring with a flat underside and a round top
  Mesh m;
  Profile p{{33, 0, 0}, {57, 0, 6}};
  curve(p, 16, [](double s) {
    double a = s * kPi;
    return dvec2(45 + 12 * std::cos(a), 12 * std::sin(a));
  });
  add_revolution(m, p, 120, true, {});
  return m;
}

Mesh funnel() {  // a thin-walled cone and spout, open at both ends
  Mesh m;
  add_revolution(
      m, {{7, 0, 0}, {10, 60, 12}, {75, 148, 24}, {76, 150, 1}, {73.5, 150, 1}, {7.5, 62, 24}, {4.5, 0, 12}, {7, 0, 1}},
      64, true, {});
  return m;
}

// ---- cones and pyramids -----------------------------------------------------

Mesh traffic_cone() {  // square base, cone with two grooved bands
  Mesh m;
  auto base = mark(m);
  add_rounded_box(m, {60, 60, 4}, 2.5, 12);
  place(m, base, glm::dmat3(1.0), {0, 0, 4});
  add_revolution(m, {{0, 7, 0}, {48, 7, 6}, {7, 198, 40}, {5, 200, 1}, {0, 200, 2}}, 64, false, {},
                 [](double, double r, double z) {
                   bool band = (z > 90 && z < 110) || (z > 140 && z < 155);
                   return band && r > 6 ? -1.2 : 0.0;
                 });
  return m;
}

Mesh pyramid() {  // a square pyramid
  Mesh m;
  auto p = mark(m);
  add_revolution(m, {{0, 0, 0}, {50 * std::sqrt(2.0), 0, 8}, {0, 80, 16}}, 4, false, {});
  place(m, p, rot_z(45), {});
  return m;
}

Mesh cone() {  // a plain round cone with a blunt tip
  Mesh m;
  add_revolution(m, {{0, 0, 0}, {40, 0, 8}, {3, 118, 30}, {0, 120, 2}}, 96, false, {});
  return m;
}

// ---- fruit and food -----------------------------------------------------------

Mesh apple() {  // dimpled at both poles, wider near the top, with a stalk
  Mesh m;
  add_revolution(m,
                 polar_profile(40, 40,
                               [](double a) {
                                 double dimple =
                                     0.22 * std::exp(-a * a / 0.12) + 0.3 * std::exp(-(kPi - a) * (kPi - a) / 0.1);
                                 return 40 * (1 - 0.08 * std::cos(a)) * (1 - dimple);
                               }),
                 80, false, {});
  add_revolution(m, {{0, 0, 0}, {2, 0, 1}, {1.6, 22, 6}, {0, 22, 1}}, 12, false, {0, 0, 66});
  return m;
}

Mesh orange() {  // a sphere with twelve shallow segments and a navel at the top
  Mesh m;
  add_revolution(m, polar_profile(38, 40, [](double a) { return 38 - 3 * std::exp(-(kPi - a) * (kPi - a) / 0.03); }),
                 96, false, {}, [](double th, double, double z) {
                   double lat = std::sqrt(std::max(0.0, 1 - (z - 38) * (z - 38) / (38.0 * 38.0)));
                   return -1.2 * lat * std::pow(std::abs(std::cos(6 * th)), 6);
                 });
  return m;
}

Mesh pear() {  // a wide bottom, a narrow neck and a stalk
  Mesh m;
  add_revolution(m,
                 polar_profile(40, 48,
                               [](double a) {
                                 double bulge = 36 * (1 - 0.35 * std::pow(std::max(0.0, -std::cos(a)), 1.5));
                                 double neck =
                                     1 + 0.9 * std::pow(std::max(0.0, -std::cos(a)), 3);  // stretches the top upwards
                                 return bulge * neck * (1 - 0.15 * std::exp(-a * a / 0.08));
                               }),
                 80, false, {});
  add_revolution(m, {{0, 0, 0}, {2, 0, 1}, {1.5, 18, 6}, {0, 18, 1}}, 12, false, {0, 0, 82});
  return m;
}

Mesh egg() {  // pointier at the top than at the bottom
  Mesh m;
  add_revolution(m,
                 polar_profile(27, 40,
                               [](double a) {
                                 double c = std::cos(a);
                                 return 22 / std::sqrt(std::sin(a) * std::sin(a) * (1 - 0.18 * c) + c * c * 0.45);
                               }),
                 64, false, {});
  return m;
}

Mesh banana() {  // a curved tapering fruit with a stalk at one end
  Mesh m;
  Sweep s;
  s.path = [](double t) {
    double a = (-45 + 90 * t) * kPi / 180;
    return dvec3(130 * std::sin(a), 0.0, 130 * (1 - std::cos(a)));
  };
  s.up = {0, 1, 0};
  s.radius = [](double t) { return 18 * std::pow(std::sin(kPi * std::clamp(t * 0.93, 0.0, 1.0)), 0.6); };
  s.n_t = 48;
  s.n_phi = 20;
  add_sweep(m, s);
  Sweep stalk;
  stalk.path = [](double t) {
    double a = (39 + 10 * t) * kPi / 180;
    return dvec3(130 * std::sin(a), 0.0, 130 * (1 - std::cos(a)) + 3 * t);
  };
  stalk.up = {0, 1, 0};
  stalk.radius = [](double) { return 4.0; };
  stalk.n_t = 8;
  stalk.n_phi = 10;
  add_sweep(m, stalk);
  return m;
}

Mesh mushroom() {  // a stem and a domed cap with a rounded edge
  Mesh m;
  Profile p{{0, 0, 0}, {15, 0, 4}, {12, 8, 3}, {11, 40, 8}, {36, 43, 6}};
  curve(p, 8, [](double s) {
    double a = -kPi / 2 + s * kPi;
    return dvec2(36 + 4 * std::cos(a), 47 + 4 * std::sin(a));
  });
  curve(p, 14, [](double s) {
    double a = s * kPi / 2;
    return dvec2(36 * std::cos(a), 51 + 27 * std::sin(a));
  });
  p.back().r = 0;
  add_revolution(m, p, 80, false, {});
  return m;
}

// ---- vessels and kitchen ------------------------------------------------------

Mesh vase() {  // a fluted vase with a narrow neck and a flared mouth
  Mesh m;
  Profile out{{0, 0, 0}, {36, 0, 6}, {40, 4, 2}};
  curve(out, 24, [](double s) {
    double z = 4 + 216 * s;
    double r =
        40 + 18 * std::sin(kPi * std::min(1.0, z / 150)) - 14 * smoothstep(120, 180, z) + 12 * smoothstep(185, 220, z);
    return dvec2(r, z);
  });
  add_revolution(m, vessel(out, 3, 6), 96, false, {}, [](double th, double r, double z) {
    if (z < 10 || z > 150 || r < 36) return 0.0;
    return 2.0 * std::pow(std::abs(std::cos(6 * th)), 3) * std::sin(kPi * (z - 10) / 140);
  });
  return m;
}

Mesh flower_pot() {  // a tapered pot with a thick band at the rim
  Mesh m;
  add_revolution(m, vessel({{0, 0, 0}, {46, 0, 8}, {50, 3, 2}, {63, 100, 20}, {70, 104, 2}, {70, 130, 6}}, 6, 8), 72,
                 false, {});
  return m;
}

Mesh kettle() {  // a closed kettle: body, domed lid with knob, spout and side handle
  Mesh m;
  Profile p{{0, 0, 0}, {66, 0, 10}, {72, 5, 2}, {74, 70, 14}};
  curve(p, 10, [](double s) { return dvec2(74 - 26 * std::sin(s * kPi / 2), 70 + 80 * s); });
  p.insert(p.end(), {{50, 152, 1}, {46, 152, 1}});
  curve(p, 8, [](double s) { return dvec2(46 * std::cos(s * kPi / 2), 152 + 12 * std::sin(s * kPi / 2)); });
  add_revolution(m, p, 96, false, {});
  add_revolution(m, {{0, 0, 0}, {6, 0, 2}, {6, 8, 2}, {12, 14, 3}, {0, 20, 4}}, 24, false, {0, 0, 160});
  Sweep spout;
  spout.path = [](double t) { return dvec3(60 + 55 * t, 0.0, 40 + 85 * t * t); };
  spout.up = {0, 1, 0};
  spout.radius = [](double t) { return 14 - 8 * t; };
  spout.n_t = 16;
  spout.n_phi = 18;
  add_sweep(m, spout);
  add_handle(m, {-45, 0, 130}, {-70, 0, 40}, -50, 6, 1.5);
  return m;
}

Mesh teapot() {  // a squat round teapot with a curved spout, loop handle and lid knob
  Mesh m;
  Profile p{{0, 0, 0}, {40, 0, 8}, {44, 3, 2}};
  curve(p, 18, [](double s) {  // an ellipse from r = 44 at the bottom to r = 36 at the top
    double a = -0.89 + s * (1.03 + 0.89);
    return dvec2(70 * std::cos(a), 55 + 52 * std::sin(a));
  });
  p.insert(p.end(), {{36, 104, 2}, {36, 108, 2}});
  curve(p, 6, [](double s) { return dvec2(36 * std::cos(s * kPi / 2), 108 + 10 * std::sin(s * kPi / 2)); });
  add_revolution(m, p, 96, false, {});
  add_revolution(m, polar_profile(8, 10, [](double) { return 8.0; }), 16, false, {0, 0, 112});
  Sweep spout;
  spout.path = [](double t) { return dvec3(40 + 70 * t, 0.0, 40 + 50 * std::sin(t * kPi / 2) + 10 * t * t); };
  spout.up = {0, 1, 0};
  spout.radius = [](double t) { return 12 - 7 * t; };
  spout.n_t = 18;
  spout.n_phi = 16;
  add_sweep(m, spout);
  add_handle(m, {-50, 0, 88}, {-55, 0, 30}, -42, 5.5, 1.4);
  return m;
}

Mesh saucepan() {  // an open pot with a long handle rising from its side
  Mesh m;
  add_revolution(m, vessel({{0, 0, 0}, {70, 0, 12}, {74, 4, 2}, {74, 80, 16}, {76, 82, 1}}, 3, 4), 72, false, {});
  auto handle = mark(m);
  add_rounded_box(m, {52, 12, 7}, 5, 8);
  place(m, handle, rot_y(-12), {122, 0, 82});
  return m;
}

// ---- lathe-turned odds and ends ---------------------------------------------

Mesh baseball_bat() {  // knob, thin handle, long barrel with a round end
  Mesh m;
  Profile p{{0, 0, 0}, {16, 0, 4}, {17, 3, 1}, {15, 7, 2}, {11, 10, 2}, {11.5, 100, 16}};
  curve(p, 20, [](double s) { return dvec2(11.5 + 19 * smoothstep(0, 1, s), 100 + 100 * s); });
  p.push_back({30.5, 232, 8});
  curve(p, 8, [](double s) {
    double a = s * kPi / 2;
    return dvec2(30.5 * std::cos(a), 232 + 18 * std::sin(a));
  });
  add_revolution(m, p, 64, false, {});
  return m;
}

Mesh hex_nut() {  // a hexagonal nut, corners chamfered on the top face only
  Mesh m;
  add_revolution(m, {{13, 0, 0}, {30, 0, 4}, {30, 21, 8}, {30, 25, 6}, {13, 25, 4}, {13, 0, 8}}, 96, true, {},
                 [](double th, double r, double z) {
                   if (r < 13.5) return 0.0;
                   double local = std::fmod(th, kPi / 3) - kPi / 6;
                   double hex = 25 / std::cos(local);
                   double outer = std::min(hex, 26.5 + (25 - z) * 1.6);  // the chamfer cone
                   return 13 + (r - 13) * (outer - 13) / 17 - r;
                 });
  return m;
}

// ---- flat and boxy things ---------------------------------------------------

Mesh smartphone() {  // a slab with rounded edges, a camera bump and side buttons
  Mesh m;
  add_rounded_box(m, {36, 75, 4}, 3.5, 12);
  auto cam = mark(m);
  add_rounded_box(m, {12, 14, 1.6}, 1.4, 6);
  place(m, cam, glm::dmat3(1.0), {-20, 57, -5});
  auto buttons = mark(m);
  add_rounded_box(m, {1.5, 9, 1.5}, 1.2, 4);
  place(m, buttons, glm::dmat3(1.0), {36, 30, 0});
  return m;
}

Mesh remote() {  // a soft-edged bar with a button grid and a round d-pad
  Mesh m;
  add_rounded_box(m, {22, 90, 10}, 6, 12);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      add_revolution(m, {{0, 0, 0}, {4, 0, 2}, {4, 2, 2}, {0, 3, 3}}, 16, false, {-11.0 + 11 * i, -62.0 + 12 * j, 9.5});
  add_torus(m, {0, 35, 10}, {1, 0, 0}, {0, 1, 0}, 12, 3, 40, 10);
  add_revolution(m, {{0, 0, 0}, {5, 0, 2}, {5, 2, 2}, {0, 3, 3}}, 20, false, {0, 35, 9.5});
  return m;
}

Mesh book() {  // a hardback: page block, overhanging boards, a rounded spine
  Mesh m;
  add_box(m, {2, 0, 0}, {112, 75, 12.5}, 20);
  for (double z : {-14.0, 14.0}) {
    auto board = mark(m);
    add_rounded_box(m, {115, 78, 1.6}, 1.2, 30);
    place(m, board, glm::dmat3(1.0), {3, 0, z});
  }
  auto spine = mark(m);
  add_revolution(m, {{0, -78, 0}, {15.6, -78, 3}, {15.6, 78, 30}, {0, 78, 3}}, 48, false, {});
  place(m, spine, rot_x(-90), {-105, 0, 0});
  return m;
}

Mesh tissue_box() {  // a box with an oval rim round the opening on top
  Mesh m;
  add_rounded_box(m, {115, 62, 45}, 4, 14);
  auto rim = mark(m);
  add_torus(m, {}, {1, 0, 0}, {0, 1, 0}, 22, 3, 64, 10);
  place(m, rim, glm::dmat3(dvec3(3, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)), {0, 0, 45});
  return m;
}

Mesh toy_cube() {  // a 40 mm block with a different raised shape on three faces
  Mesh m;
  add_rounded_box(m, {20, 20, 20}, 3, 5);
  add_revolution(m, {{0, 0, 0}, {10, 0, 3}, {10, 2.5, 1}, {0, 2.5, 3}}, 32, false, {0, 0, 19.5});
  auto bar = mark(m);
  add_rounded_box(m, {1.5, 12, 3}, 1, 4);
  place(m, bar, glm::dmat3(1.0), {20.5, 0, 0});
  auto tri = mark(m);
  add_extrusion(m, regular_polygon(3, 10), 0, 2.5);
  place(m, tri, rot_x(-90), {0, 19.5, 0});
  return m;
}

Mesh toy_brick() {  // a large 2 x 4 building brick
  Mesh m;
  add_rounded_box(m, {32, 16, 9.6}, 1.0, 6);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j)
      add_revolution(m, {{0, 0, 0}, {4.8, 0, 3}, {4.8, 4.5, 3}, {4.3, 5, 1}, {0, 5, 3}}, 32, false,
                     {-24.0 + 16 * i, -8.0 + 16 * j, 9.1});
  return m;
}

Mesh arch_block() {  // a block with a round arch cut from below
  Mesh m;
  std::vector<dvec2> outline{{-50, 0}};
  append_arc(outline, {0, 0}, 30, 180, 0, 24);
  outline.insert(outline.end(), {{50, 0}, {50, 50}, {-50, 50}});
  auto a = mark(m);
  add_extrusion(m, outline, -20, 20, 4);
  place(m, a, rot_x(90), {});
  return m;
}

Mesh triangle_block() {  // a triangular prism with a raised disc on top
  Mesh m;
  add_extrusion(m, regular_polygon(3, 70 / std::sqrt(3.0)), 0, 35, 4);
  add_revolution(m, {{0, 0, 0}, {10, 0, 3}, {10, 2.5, 1}, {0, 2.5, 3}}, 32, false, {0, 0, 34.5});
  return m;
}

Mesh star_block() {  // a five-pointed star with a dome in the middle of its top
  Mesh m;
  std::vector<dvec2> star;
  for (int k = 0; k < 10; ++k) {
    double a = (90 + 36 * k) * kPi / 180, r = k % 2 ? 24 : 55;
    star.push_back({r * std::cos(a), r * std::sin(a)});
  }
  add_extrusion(m, star, 0, 25, 4);
  add_revolution(m, polar_profile(0, 12, [](double) { return 16.0; }), 40, false, {0, 0, 20});
  return m;
}

Mesh computer_mouse() {  // a long dome with a scroll wheel at the front
  Mesh m;
  auto body = mark(m);
  Profile p{{0, 0, 0}, {56, 0, 10}, {60, 4, 2}};
  curve(p, 14, [](double s) {
    double a = s * kPi / 2;
    return dvec2(60 * std::cos(a), 4 + 34 * std::sin(a));
  });
  add_revolution(m, p, 96, false, {});
  place(m, body, glm::dmat3(dvec3(1, 0, 0), dvec3(0, 0.53, 0), dvec3(0, 0, 1)), {});
  auto wheel = mark(m);
  add_revolution(m, {{0, -2.5, 0}, {8, -2.5, 3}, {8, 2.5, 2}, {0, 2.5, 3}}, 24, false, {});
  place(m, wheel, rot_x(90), {32, 0, 28});
  return m;
}

Mesh stapler() {  // base plate, top arm, hinge block and anvil
  Mesh m;
  add_rounded_box(m, {78, 19, 5}, 2.5, 12);
  auto arm = mark(m);
  add_rounded_box(m, {72, 15, 9}, 5, 12);
  place(m, arm, rot_y(-4), {2, 0, 24});
  auto hinge = mark(m);
  add_rounded_box(m, {10, 16, 12}, 3, 8);
  place(m, hinge, glm::dmat3(1.0), {-64, 0, 14});
  auto anvil = mark(m);
  add_rounded_box(m, {10, 8, 1.5}, 1, 4);
  place(m, anvil, glm::dmat3(1.0), {60, 0, 5});
  return m;
}

// ---- tools ----------------------------------------------------------------

Mesh hammer() {  // a handle, a head with a round face on one side and a curved claw on the other
  Mesh m;
  auto handle = mark(m);
  add_rounded_box(m, {11, 15, 115}, 6, 12);
  place(m, handle, glm::dmat3(1.0), {0, 0, 115});
  auto head = mark(m);
  add_rounded_box(m, {30, 13, 15}, 3, 8);
  place(m, head, glm::dmat3(1.0), {8, 0, 230});
  auto face = mark(m);
  add_revolution(m, {{0, 0, 0}, {15, 0, 3}, {16, 2, 1}, {16, 28, 6}, {14, 30, 2}, {0, 30, 4}}, 48, false, {});
  place(m, face, rot_y(90), {30, 0, 230});
  auto claw = mark(m);
  add_extrusion(m, {{0, -10}, {-30, -11}, {-55, -15}, {-70, -24}, {-66, -16}, {-48, -4}, {-25, 5}, {0, 10}}, -11, 11,
                2);
  place(m, claw, rot_x(90), {-18, 0, 232});
  return m;
}

Mesh wrench() {  // a flat combination spanner: ring end, handle, angled open jaw
  Mesh m;
  std::vector<dvec2> handle;
  append_arc(handle, {-75, 0}, 8, 90, 270, 8);
  append_arc(handle, {75, 0}, 9, -90, 90, 8);
  add_extrusion(m, handle, -3.5, 3.5);
  add_revolution(m, {{10, -5, 0}, {18, -5, 3}, {18, 5, 3}, {10, 5, 3}, {10, -5, 3}}, 48, true, {-88, 0, 0});
  std::vector<dvec2> jaw;
  append_arc(jaw, {0, 0}, 21, 22, 338, 40);
  jaw.insert(jaw.end(), {{-3, -7.8}, {-3, 7.8}});
  auto j = mark(m);
  add_extrusion(m, jaw, -4, 4);
  place(m, j, rot_z(15), {95, 0, 0});
  return m;
}

Mesh pliers() {  // jaws, a pivot, two curved handles (one with a hooked end)
  Mesh m;
  add_extrusion(m, {{0, -10}, {45, -3}, {55, 0}, {45, 3}, {0, 10}, {-8, 0}}, -5, 5, 2);
  add_revolution(m, {{0, -7, 0}, {10, -7, 3}, {10, 7, 4}, {0, 7, 3}}, 32, false, {});
  for (double side : {-1.0, 1.0}) {
    Sweep s;
    s.path = [side](double t) { return dvec3(-4 - 125 * t, side * (5 + 22 * t - 6 * t * t), 0.0); };
    s.radius = [](double t) { return 6 + 1.5 * t; };
    s.flatten = 0.8;
    s.n_t = 24;
    s.n_phi = 14;
    add_sweep(m, s);
  }
  add_revolution(m, polar_profile(0, 10, [](double) { return 9.0; }), 20, false, {-129, 21, 0});
  return m;
}

// A screwdriver along z: a fluted handle (flutes, shaft radius, length, tip).
Mesh screwdriver(int flutes, double handle_r, double handle_len, double shaft_r, double shaft_len, bool phillips) {
  Mesh m;
  const double z0 = handle_len, z1 = handle_len + shaft_len;
  Profile p{{0, 0, 0},
            {handle_r - 3, 0, 4},
            {handle_r, 3, 2},
            {handle_r, handle_len - 15, 20},
            {handle_r - 5, handle_len - 4, 4},
            {shaft_r + 3, z0, 3},
            {shaft_r, z0 + 2, 2},
            {shaft_r, z1 - 12, 8}};
  p.insert(p.end(), {{shaft_r, z1 - 3, 8}, {phillips ? 0.8 : shaft_r * 0.85, z1, 4}, {0, z1, 2}});
  add_revolution(m, p, 72, false, {}, [=](double th, double r, double z) {
    if (z > 4 && z < handle_len - 16 && r > handle_r - 0.1) return -2.0 * smoothstep(0.5, 0.85, std::cos(flutes * th));
    if (z > z1 - 12 && r < shaft_r + 0.1) {
      if (phillips) return -0.45 * r * smoothstep(0.6, 0.9, std::cos(4 * th)) * smoothstep(z1 - 10, z1 - 6, z);
      double c = std::abs(std::cos(th)), limit = c > 1e-6 ? 0.6 / c : 1e9;  // the flat blade
      return (std::min(r, limit) - r) * smoothstep(z1 - 12, z1 - 6, z);
    }
    return 0.0;
  });
  return m;
}
Mesh screwdriver_flat() { return screwdriver(6, 16, 100, 3.5, 100, false); }
Mesh screwdriver_phillips() { return screwdriver(8, 14, 95, 3, 85, true); }

Mesh shoe() {  // a sole shaped like a foot, a domed upper and an ankle collar
  Mesh m;
  std::vector<dvec2> sole;
  for (int k = 0; k < 48; ++k) {
    double a = 2 * kPi * k / 48, x = 125 * std::cos(a);
    double w = 45 - 10 * std::exp(-(x + 10) * (x + 10) / 900.0) - 8 * smoothstep(-60, -125, x);  // waist, heel
    sole.push_back({x, w * std::sin(a)});
  }
  add_extrusion(m, sole, 0, 14, 2);
  auto upper = mark(m);
  Profile p{{0, 0, 0}, {95, 0, 12}};
  curve(p, 14, [](double s) {
    double a = s * kPi / 2;
    return dvec2(95 * std::cos(a), 75 * std::sin(a));
  });
  add_revolution(m, p, 72, false, {});
  place(m, upper, glm::dmat3(dvec3(1.2, 0, 0), dvec3(0, 0.42, 0), dvec3(0, 0, 1)), {-8, 0, 10});
  auto collar = mark(m);
  add_torus(m, {}, {1, 0, 0}, {0, 1, 0}, 20, 6, 48, 12);
  place(m, collar, glm::dmat3(dvec3(1.3, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, 1)), {-45, 0, 72});
  return m;
}

}  // namespace

std::string axis_symmetry(const char* axis) { return std::string(R"({"type": "axis", "axis": )") + axis + "}"; }
std::string cyclic_symmetry(int order, const char* axis) {
  return std::string(R"({"type": "cyclic", "axis": )") + axis + R"(, "order": )" + std::to_string(order) + "}";
}

std::vector<ObjectSpec> household_objects() {
  const std::string none = "\"none\"", axis = axis_symmetry();
  return {
      // household10: one of each family
      {"mug_straight", mug_straight, none},
      {"water_bottle", water_bottle, cyclic_symmetry(24)},
      {"soda_can", soda_can, axis},
      {"dinner_plate", dinner_plate, axis},
      {"tape_roll", tape_roll, axis},
      {"pyramid", pyramid, cyclic_symmetry(4)},
      {"apple", apple, axis},
      {"smartphone", smartphone, none},
      {"hammer", hammer, none},
      {"toy_brick", toy_brick, cyclic_symmetry(2)},
      // household25
      {"wine_glass", wine_glass, axis},
      {"jam_jar", jam_jar, cyclic_symmetry(30)},
      {"spray_can", spray_can, none},
      {"cereal_bowl", cereal_bowl, axis},
      {"ring_toss", ring_toss, axis},
      {"traffic_cone", traffic_cone, cyclic_symmetry(4)},
      {"orange", orange, cyclic_symmetry(12)},
      {"banana", banana, none},
      {"kettle", kettle, none},
      {"remote", remote, none},
      {"book", book, cyclic_symmetry(2, "[1, 0, 0]")},
      {"star_block", star_block, cyclic_symmetry(5)},
      {"computer_mouse", computer_mouse, none},
      {"wrench", wrench, none},
      {"screwdriver_flat", screwdriver_flat, cyclic_symmetry(2)},
      // household50
      {"mug_tapered", mug_tapered, none},
      {"espresso_cup", espresso_cup, none},
      {"teacup", teacup, none},
      {"wine_bottle", wine_bottle, axis},
      {"food_tin", food_tin, axis},
      {"mixing_bowl", mixing_bowl, axis},
      {"funnel", funnel, axis},
      {"cone", cone, axis},
      {"pear", pear, axis},
      {"egg", egg, axis},
      {"mushroom", mushroom, axis},
      {"vase", vase, cyclic_symmetry(12)},
      {"flower_pot", flower_pot, axis},
      {"baseball_bat", baseball_bat, axis},
      {"hex_nut", hex_nut, cyclic_symmetry(6)},
      {"teapot", teapot, none},
      {"saucepan", saucepan, none},
      {"tissue_box", tissue_box, cyclic_symmetry(2)},
      {"toy_cube", toy_cube, none},
      {"arch_block", arch_block, cyclic_symmetry(2)},
      {"triangle_block", triangle_block, cyclic_symmetry(3)},
      {"stapler", stapler, none},
      {"pliers", pliers, none},
      {"screwdriver_phillips", screwdriver_phillips, cyclic_symmetry(4)},
      {"shoe", shoe, none},
  };
}

}  // namespace sva::assets
