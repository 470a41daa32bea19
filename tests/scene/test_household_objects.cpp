// The household set (assets/generator/household_objects.cpp, the scenes
// household{10,25,50}.json): every mesh is a union of closed, outward-facing
// shells at the real size its scene states, and the small scenes are the first
// objects of the large one with the same settings, so that only the number of
// objects changes between them.
#include <catch2/catch.hpp>

#include <sva/scene.hpp>
#include <sva/sim/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>

namespace {

using sva::sim::Mesh;

// Shells meet their neighbours at seams computed alike but stored as floats:
// vertices closer than this are one point.
constexpr double kWeldMm = 1e-3;

// The index of each vertex's representative: the first vertex within kWeldMm
// (a hash grid of that cell size, searched in the 27 neighbouring cells).
std::vector<std::uint32_t> weld(const Mesh& m) {
  auto cell = [](double x) { return static_cast<std::int64_t>(std::floor(x / kWeldMm)); };
  auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
           (static_cast<std::uint64_t>(z) * 83492791u);
  };
  std::unordered_multimap<std::uint64_t, std::uint32_t> grid;
  std::vector<std::uint32_t> rep(m.positions.size());
  for (std::uint32_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 p(m.positions[i]);
    const std::int64_t cx = cell(p.x), cy = cell(p.y), cz = cell(p.z);
    rep[i] = i;
    for (std::int64_t dx = -1; dx <= 1 && rep[i] == i; ++dx)
      for (std::int64_t dy = -1; dy <= 1 && rep[i] == i; ++dy)
        for (std::int64_t dz = -1; dz <= 1 && rep[i] == i; ++dz) {
          auto [lo, hi] = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
          for (auto it = lo; it != hi; ++it)
            if (glm::length(glm::dvec3(m.positions[it->second]) - p) <= kWeldMm) {
              rep[i] = it->second;
              break;
            }
        }
    if (rep[i] == i) grid.emplace(key(cx, cy, cz), i);
  }
  return rep;
}

struct Closure {
  std::size_t unmatched_edges = 0;  // directed edges not matched by as many reversed ones
  std::size_t shells = 0;
  std::size_t inside_out_shells = 0;  // shells of negative volume
  double volume = 0;
};

// Closed: after welding, every directed edge is matched by as many reversed
// ones (each edge is shared by faces on both sides, consistently oriented).
// Outward: every connected shell encloses a positive volume.
Closure closure(const Mesh& m) {
  const std::vector<std::uint32_t> rep = weld(m);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::vector<std::uint32_t> parent(m.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : m.triangles) {
    const std::uint32_t v[3] = {rep[t.x], rep[t.y], rep[t.z]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // collapsed by the weld: no area, no edges
    for (int k = 0; k < 3; ++k) {
      ++directed[{v[k], v[(k + 1) % 3]}];
      parent[find(v[k])] = find(v[(k + 1) % 3]);
    }
  }
  Closure c;
  for (const auto& [edge, count] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != count) ++c.unmatched_edges;
  }
  std::map<std::uint32_t, double> shell_volume;
  for (const auto& t : m.triangles) {
    const glm::dvec3 a(m.positions[rep[t.x]]), b(m.positions[rep[t.y]]), d(m.positions[rep[t.z]]);
    shell_volume[find(rep[t.x])] += glm::dot(a, glm::cross(b, d)) / 6;
  }
  c.shells = shell_volume.size();
  for (const auto& [root, v] : shell_volume) {
    c.inside_out_shells += v <= 0;
    c.volume += v;
  }
  return c;
}

double largest(glm::dvec3 e) { return std::max({e.x, e.y, e.z}); }

}  // namespace

TEST_CASE("household objects: closed outward shells at their real, varied sizes") {
  const sva::Scene scene = sva::load_scene("household50");
  REQUIRE(scene.objects.size() == 50);
  std::set<double> sizes;
  std::vector<std::pair<double, double>> area_volume;
  for (const sva::SceneObject& o : scene.objects) {
    INFO(o.name << " (" << o.mesh.string() << ")");
    const Mesh m = sva::sim::load_mesh(o.mesh);
    const Closure c = closure(m);
    CHECK(c.unmatched_edges == 0);
    CHECK(c.inside_out_shells == 0);
    CHECK(m.triangles.size() <= 16000);  // modest, so that simulating 50 objects stays quick
    // The scene keeps the mesh's own millimetres: size_mm is its largest dimension.
    CHECK(largest(m.extent()) == Approx(o.size_mm).margin(0.06));
    CHECK(o.size_mm >= 40);
    CHECK(o.size_mm <= 250);
    CHECK(o.inertial_radius_mm == Approx(o.size_mm / 2).margin(0.06));
    const Mesh fitted = sva::sim::load_object_mesh(o);
    CHECK(largest(fitted.extent()) == Approx(o.size_mm).epsilon(1e-4));
    sizes.insert(std::round(o.size_mm));
    area_volume.emplace_back(m.area(), c.volume);
  }
  // Real sizes, not one size for all: spread from small to large.
  CHECK(sizes.size() >= 30);
  CHECK(*sizes.begin() <= 60);
  CHECK(*sizes.rbegin() >= 230);
  // No two objects are the same solid (same surface area and volume to 1%).
  for (std::size_t i = 0; i < area_volume.size(); ++i)
    for (std::size_t j = i + 1; j < area_volume.size(); ++j) {
      INFO(scene.objects[i].name << " and " << scene.objects[j].name);
      const auto [a1, v1] = area_volume[i];
      const auto [a2, v2] = area_volume[j];
      CHECK((std::abs(a1 - a2) > 0.01 * std::max(a1, a2) || std::abs(v1 - v2) > 0.01 * std::max(v1, v2)));
    }
}

TEST_CASE("household scenes: 10 and 25 are the first objects of 50, everything else alike") {
  const sva::Scene all = sva::load_scene("household50");
  for (const char* name : {"household10", "household25"}) {
    INFO(name);
    const sva::Scene s = sva::load_scene(name);
    REQUIRE(s.objects.size() == (std::string(name) == "household10" ? 10u : 25u));
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const sva::SceneObject &a = s.objects[i], &b = all.objects[i];
      CHECK(a.name == b.name);
      CHECK(a.mesh == b.mesh);
      CHECK(a.size_mm == b.size_mm);
      CHECK(a.symmetry.kind == b.symmetry.kind);
      CHECK(a.symmetry.rotations.size() == b.symmetry.rotations.size());
    }
    // Everything but the objects and the name is the same scene.
    sva::Scene same = all;
    same.objects = s.objects;
    same.name = s.name;
    CHECK(sva::scene_to_json(same) == sva::scene_to_json(s));
  }
}

TEST_CASE("household objects: the closure check finds holes and inside-out shells") {
  // A tetrahedron facing out, then with a face missing, then turned inside out.
  Mesh m;
  m.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  Closure c = closure(m);
  CHECK(c.unmatched_edges == 0);
  CHECK(c.shells == 1);
  CHECK(c.inside_out_shells == 0);
  CHECK(c.volume == Approx(1000.0 / 6));
  Mesh open = m;
  open.triangles.pop_back();
  CHECK(closure(open).unmatched_edges == 3);
  Mesh inverted = m;
  for (auto& t : inverted.triangles) std::swap(t.y, t.z);
  CHECK(closure(inverted).inside_out_shells == 1);
  // A second copy of a vertex a float's rounding away is the same point; one 0.01 mm away is a hole.
  Mesh split = m;
  split.positions.push_back(split.positions[3] + glm::vec3(0, 0, 1e-5f));
  split.triangles[3].y = 4;
  CHECK(closure(split).unmatched_edges == 0);
  split.positions[4] = split.positions[3] + glm::vec3(0, 0, 0.01f);
  CHECK(closure(split).unmatched_edges > 0);
}

TEST_CASE("look-alikes: families of 3-5 near-twins, closed outward shells at real sizes, and household100 holds them") {
  const sva::Scene scene = sva::load_scene("lookalikes");
  std::map<std::string, int> members;
  for (const sva::SceneObject& o : scene.objects) {
    INFO(o.name << " (" << o.mesh.string() << ")");
    REQUIRE_FALSE(o.family.empty());
    ++members[o.family];
    const Mesh m = sva::sim::load_mesh(o.mesh);
    const Closure c = closure(m);
    CHECK(c.unmatched_edges == 0);
    CHECK(c.inside_out_shells == 0);
    CHECK(m.triangles.size() <= 16000);
    CHECK(largest(m.extent()) == Approx(o.size_mm).margin(0.06));
    CHECK(o.size_mm >= 40);
    CHECK(o.size_mm <= 250);
  }
  CHECK(members.size() >= 10);
  for (const auto& [family, n] : members) {
    INFO(family);
    CHECK(n >= 3);
    CHECK(n <= 5);
  }
  // household100: the 50 household objects (no family), then the look-alikes, everything else as household50. The
  // look-alikes alone touch each object four times as often as they pair its readings.
  const sva::Scene all = sva::load_scene("household100"), h50 = sva::load_scene("household50");
  REQUIRE(all.objects.size() == 100);
  for (std::size_t i = 0; i < all.objects.size(); ++i) {
    const sva::SceneObject& o = all.objects[i];
    const sva::SceneObject& want = i < 50 ? h50.objects[i] : scene.objects[i - 50];
    CHECK(o.name == want.name);
    CHECK(o.family == want.family);
  }
  CHECK(scene.protocol.train_per_object == 4 * h50.protocol.train_per_object);
  CHECK(scene.appearance.pair_readings == h50.protocol.train_per_object);
  CHECK(h50.appearance.pair_readings == 0);
  sva::Scene same = h50;
  same.objects = all.objects;
  same.name = all.name;
  CHECK(sva::scene_to_json(same) == sva::scene_to_json(all));
}
