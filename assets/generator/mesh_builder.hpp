#pragma once
// The construction helpers every generated object is made of. An object is a
// union of closed shells (the simulator only touches accessible points, so
// faces buried inside another shell are never sampled); each helper adds one
// closed, outward-facing shell to the mesh. Units are millimetres.
#include <sva/sim/mesh.hpp>

#include <functional>
#include <vector>

namespace sva::assets {

using glm::dvec2;
using glm::dvec3;
using sim::Mesh;

constexpr double kPi = 3.14159265358979323846;

double smoothstep(double a, double b, double x);
double fract(double x);

// Rotations by `deg` degrees about the axes.
glm::dmat3 rot_x(double deg);
glm::dmat3 rot_y(double deg);
glm::dmat3 rot_z(double deg);

// Where a shell starts in the mesh, so that it can be placed after it is made.
struct ShellMark {
  std::size_t vertices = 0, triangles = 0;
};
ShellMark mark(const Mesh& m);
// Moves the shells added since `from`: p -> offset + linear * p (a mirror
// turns their triangles round so that they keep facing out).
void place(Mesh& m, ShellMark from, const glm::dmat3& linear, dvec3 offset);

// A (nu x nv) grid surface p(u, v), u, v in [0, 1]; the outward normal is
// dp/du x dp/dv. Wrapped directions reuse the first row of vertices; rows that
// collapse to a point (a pole) leave only their non-degenerate triangles.
void add_grid(Mesh& m, int nu, int nv, bool wrap_u, bool wrap_v, const std::function<dvec3(double, double)>& p);

// A solid of revolution about z (the lathe). The profile runs from the bottom
// of the axis outwards, up the outside and back to the axis (or round a closed
// loop); each point carries how many segments lead to it from the previous one.
// dr(theta, r, z) displaces the radius (ribs, flutes, knurling, flats).
struct ProfilePoint {
  double r, z;
  int segments;
};
void add_revolution(Mesh& m, const std::vector<ProfilePoint>& profile, int n_theta, bool closed_loop, dvec3 centre,
                    const std::function<double(double theta, double r, double z)>& dr = nullptr);

// Lathe profiles: a profile is built from fixed points and sampled curves.
using Profile = std::vector<ProfilePoint>;

// Appends n points of the curve f(s), s in (0, 1], one segment each.
void curve(Profile& p, int n, const std::function<dvec2(double)>& f);

// A closed lathe profile from the bottom pole to the top pole of the polar
// curve rho(a) about (0, cz), a in [0, pi] from the bottom: fruit and eggs.
Profile polar_profile(double cz, int n, const std::function<double(double)>& rho);

// An open vessel: the outer profile (bottom pole outwards and up to the rim),
// then a rounded lip of the given wall, then the same wall inside down to a
// floor of thickness `floor` above the outer bottom.
Profile vessel(const Profile& outside, double wall, double floor);

// A box centred at `c` with half sizes `h`, each face a grid of about `cell`
// mm displaced along its normal by disp(face, s, t) (s, t: mm from the face
// centre along the face axes a, b with a x b = outward normal).
void add_box(Mesh& m, dvec3 c, dvec3 h, double cell,
             const std::function<double(int face, double s, double t)>& disp = nullptr,
             const glm::dmat3& rot = glm::dmat3(1.0));

// A box centred at the origin with half sizes `h` whose edges and corners are
// rounded with radius `r` (< every half size), `round_segments` per quarter
// round; flat parts are cut into cells of about `cell` mm.
void add_rounded_box(Mesh& m, dvec3 h, double r, double cell, int round_segments = 4);

// A torus: ring radius R in the plane of (e1, e2), tube radius r.
void add_torus(Mesh& m, dvec3 c, dvec3 e1, dvec3 e2, double R, double r, int nu, int nv);

// A tube swept along a planar path(t), t in [0, 1], whose plane has the unit
// normal `up`; the cross-section at t is an ellipse of half axes radius(t) (in
// the path's plane) and radius(t) * flatten (along `up`). With flat_caps the
// ends are closed by discs; otherwise radius must reach 0 at both ends.
struct Sweep {
  std::function<dvec3(double t)> path;
  dvec3 up{0, 0, 1};
  std::function<double(double t)> radius;
  double flatten = 1.0;
  int n_t = 32, n_phi = 16;
  bool flat_caps = true;
};
void add_sweep(Mesh& m, const Sweep& s);

// A D-shaped handle in the xz plane from `top` to `bottom` (both just inside
// the wall they join, which they leave at right angles), reaching `reach` mm
// out along x (negative: towards -x); its section is 2 radius across in the
// plane and 2 radius x flatten across it.
void add_handle(Mesh& m, dvec3 top, dvec3 bottom, double reach, double radius, double flatten);

// A prism: the simple polygon `outline` (counter-clockwise in xy, any shape)
// from z0 to z1, caps triangulated by ear clipping, sides cut into `rows`.
void add_extrusion(Mesh& m, const std::vector<dvec2>& outline, double z0, double z1, int rows = 1);

// Outlines for add_extrusion: a circular arc (centre, radius, angles in
// degrees, `n` segments, both ends included) and a regular polygon.
void append_arc(std::vector<dvec2>& out, dvec2 centre, double radius, double from_deg, double to_deg, int n);
std::vector<dvec2> regular_polygon(int sides, double radius, double start_deg = 90);

}  // namespace sva::assets
