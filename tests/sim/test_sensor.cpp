// The simulator's physics through its API: plane, sphere, cube edge, node
// transforms and mesh fitting.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/sim/simulate.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <cmath>

#include "gltf_writer.hpp"
#include "test_support.hpp"

using namespace sva;
using sva::test::TestMesh;

namespace {

double degrees(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / M_PI;
}

double mean_contact(const Reading& r, double threshold) {
  double s = 0;
  int n = 0;
  for (float p : r.pressure)
    if (p > threshold) s += p, ++n;
  return n ? s / n : 0.0;
}

TestMesh plane_mesh(float half) {
  TestMesh m;
  m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

}  // namespace

TEST_CASE("pressing a plane gives a uniform, symmetric image at the target pressure") {
  auto dir = test::temp_dir("sim-plane");
  auto file = test::write_gltf(plane_mesh(100), dir / "plane.gltf");
  sim::ObjectGeometry geom(sim::load_mesh(file));
  SkinModel skin;
  SensorSpec spec;
  sim::TactileSensor sensor(geom, spec, skin);
  for (double tilt_deg : {0.0, 8.0}) {
    double t = tilt_deg * M_PI / 180;
    sim::SensorPose start{{0.3, -0.2, 3.0}, {std::sin(t), 0.0, std::cos(t)}, {std::cos(t), 0.0, -std::sin(t)}};
    Reading r = sim::press(sensor, start, sim::ControllerSettings{}, 7).reading;
    INFO("tilt " << tilt_deg);
    REQUIRE(r.status == ControllerStatus::converged);
    CHECK(degrees(r.normal, {0, 0, 1}) < 0.5);
    CHECK(std::abs(r.position.z + 0.2) < 0.02);  // 20 kPa / 100 kPa/mm = 0.2 mm into the skin
    REQUIRE(r.pressure.size() == 36u);
    float lo = *std::min_element(r.pressure.begin(), r.pressure.end());
    float hi = *std::max_element(r.pressure.begin(), r.pressure.end());
    CHECK(hi - lo < 0.02f * hi);
    CHECK(mean_contact(r, skin.contact_threshold_kpa) == Approx(skin.target_pressure_kpa).epsilon(0.04));
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        CHECK(r.pressure[static_cast<std::size_t>(i * 6 + j)] ==
              Approx(r.pressure[static_cast<std::size_t>((5 - i) * 6 + (5 - j))]).epsilon(0.02));
        CHECK(r.pressure[static_cast<std::size_t>(i * 6 + j)] ==
              Approx(r.pressure[static_cast<std::size_t>(j * 6 + i)]).epsilon(0.02));
      }
  }
}

TEST_CASE("on a sphere the controller converges to the surface normal at the target pressure") {
  auto dir = test::temp_dir("sim-sphere");
  auto file = test::write_gltf(test::sphere_mesh(1.0f, 5), dir / "sphere.gltf");
  Scene scene;
  scene.name = "sphere";
  SceneObject obj;
  obj.name = "sphere";
  obj.mesh = file;
  obj.size_mm = 80;  // radius 40 mm, as the paper's objects
  scene.objects.push_back(obj);
  sim::SimulateOptions opt;
  opt.train_per_object = 200;
  opt.test_per_object = 0;
  opt.seed = 11;
  auto data = sim::simulate(scene, opt);
  REQUIRE(data.train.samples.size() == 200u);
  int converged = 0, normal_ok = 0, pressure_ok = 0;
  for (const auto& s : data.train.samples) {
    const Reading& r = s.reading;
    converged += r.status == ControllerStatus::converged;
    // The true outward normal under the sensor centre.
    normal_ok += r.status == ControllerStatus::converged && degrees(r.normal, glm::normalize(r.position)) <= 3.0;
    pressure_ok += std::abs(mean_contact(r, scene.skin.contact_threshold_kpa) - scene.skin.target_pressure_kpa) <=
                   0.05 * scene.skin.target_pressure_kpa;
    CHECK(std::abs(glm::length(r.normal) - 1.0) < 1e-9);
    CHECK(std::abs(glm::dot(r.normal, r.x_axis)) < 1e-9);
  }
  CHECK(converged >= 190);
  CHECK(normal_ok >= 190);
  CHECK(pressure_ok >= 190);
  CHECK(data.test.samples.empty());
}

TEST_CASE("a cube edge gives a line contact") {
  auto dir = test::temp_dir("sim-edge");
  auto file = test::write_gltf(test::box_mesh({-20, -20, -20}, {20, 20, 20}), dir / "cube.gltf");
  sim::ObjectGeometry geom(sim::load_mesh(file));
  SkinModel skin;
  sim::TactileSensor sensor(geom, SensorSpec{}, skin);
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 0, 1)), x = glm::normalize(glm::dvec3(1, 0, -1));
  sim::SensorPose start{glm::dvec3(20, 0.5, 20) + 3.0 * n, n, x};  // the edge runs along the sensor's y axis
  sim::ControllerSettings cs;
  cs.reorient = false;  // an edge is an unstable balance for a free sensor; hold the bisector
  cs.recenter = false;
  Reading r = sim::press(sensor, start, cs, 3).reading;
  REQUIRE(r.status == ControllerStatus::converged);
  int rows_in_contact = 0;
  for (int i = 0; i < 6; ++i) {
    bool any = false;
    for (int j = 0; j < 6; ++j) {
      float p = r.pressure[static_cast<std::size_t>(i * 6 + j)];
      if (p > skin.contact_threshold_kpa) {
        any = true;
        CHECK((j == 2 || j == 3));  // only the two columns either side of the edge
      }
    }
    rows_in_contact += any;
    // Every row sees the same cross-section of the edge.
    CHECK(r.pressure[static_cast<std::size_t>(i * 6 + 2)] == Approx(r.pressure[2]).epsilon(0.03));
  }
  CHECK(rows_in_contact == 6);
  // And a face of the same cube gives full contact.
  Reading face = sim::press(sensor, {{0, 0, 23}, {0, 0, 1}, {1, 0, 0}}, sim::ControllerSettings{}, 3).reading;
  REQUIRE(face.status == ControllerStatus::converged);
  for (float p : face.pressure) CHECK(p > skin.contact_threshold_kpa);
}

TEST_CASE("node transforms, strips and fans place a mesh correctly") {
  auto dir = test::temp_dir("sim-nodes");
  auto bin = dir / "box.bin";
  auto j = test::gltf_json(test::box_mesh({0, 0, 0}, {1, 1, 1}), bin);
  // Parent translates by +10 x; child rotates 90 degrees about z and scales by 2.
  const double s = std::sqrt(0.5);
  j["nodes"] = nlohmann::json::array({{{"children", {1}}, {"translation", {10, 0, 0}}},
                                      {{"mesh", 0}, {"rotation", {0, 0, s, s}}, {"scale", {2, 2, 2}}},
                                      {{"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}}});
  j["scenes"][0]["nodes"] = {0};
  test::write_json(j, dir / "nested.gltf");
  auto m = sim::load_mesh(dir / "nested.gltf");
  CHECK(m.bounds_min.x == Approx(8.0));
  CHECK(m.bounds_max.x == Approx(10.0));
  CHECK(m.bounds_min.y == Approx(0.0).margin(1e-6));
  CHECK(m.bounds_max.y == Approx(2.0));
  CHECK(m.bounds_max.z == Approx(2.0));
  CHECK(m.triangles.size() == 12u);
  CHECK(m.area() == Approx(24.0));  // scale 2: six faces of 4 mm^2
  // Missing normals are computed, unit length and outward.
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    CHECK(glm::length(glm::dvec3(m.normals[i])) == Approx(1.0));
    glm::dvec3 out = glm::dvec3(m.positions[i]) - glm::dvec3(9, 1, 1);
    CHECK(glm::dot(glm::dvec3(m.normals[i]), out) > 0);
  }
  // The matrix node is used when the scene lists it.
  j["scenes"][0]["nodes"] = {2};
  test::write_json(j, dir / "matrix.gltf");
  auto mm = sim::load_mesh(dir / "matrix.gltf");
  CHECK(mm.bounds_min.y == Approx(5.0));
  CHECK(mm.bounds_max.y == Approx(6.0));

  // A quad as a strip and as a fan: two triangles each, same area.
  TestMesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  quad.indices = {0, 1, 2, 3};
  auto strip = sim::load_mesh(test::write_gltf(quad, dir / "strip.gltf", 5));
  CHECK(strip.triangles.size() == 2u);
  CHECK(strip.area() == Approx(1.0));
  for (auto n : strip.normals) CHECK(n.z == Approx(1.0));  // consistent winding
  quad.indices = {0, 1, 3, 2};
  auto fan = sim::load_mesh(test::write_gltf(quad, dir / "fan.gltf", 6));
  CHECK(fan.triangles.size() == 2u);
  CHECK(fan.area() == Approx(1.0));

  // The scene decides size and centre.
  SceneObject o;
  o.mesh = dir / "nested.gltf";
  o.size_mm = 80;
  auto fitted = sim::load_object_mesh(o);
  CHECK(std::max({fitted.extent().x, fitted.extent().y, fitted.extent().z}) == Approx(80.0));
  CHECK(glm::length(fitted.bounds_min + fitted.bounds_max) < 1e-4);
}

TEST_CASE("letters2d readings are pressed straight down on the grid") {
  for (const char* name : {"letters2d-ideal", "letters2d"}) {
    Scene scene = load_scene(name);
    scene.objects.resize(2);
    sim::SimulateOptions opt;
    opt.train_per_object = 24;
    opt.test_per_object = 24;
    auto data = sim::simulate(scene, opt);
    REQUIRE(data.train.samples.size() == 48u);
    const double spacing = scene.protocol.grid_spacing_mm;
    // The reported pose is the truth in the ideal world, and off it by the
    // arm's errors (well within 5 sigma) in the real one.
    const double pos_tol = 5 * scene.errors.position_sigma_mm + 1e-9;
    const double normal_tol = 5 * std::sqrt(2.0) * scene.errors.normal_sigma_deg + 1e-6;
    std::size_t differs = 0;
    for (std::size_t i = 0; i < data.train.samples.size(); ++i) {
      INFO(name << " reading " << i);
      const Sample& s = data.train.samples[i];
      const Reading& r = s.reading;
      CHECK(r.status == ControllerStatus::converged);
      CHECK(s.truth.normal.z == Approx(1.0));
      // Training poses sit exactly on the 4 x 4 grid (spacing 6.8 mm, centred).
      double gx = s.truth.position.x / spacing + 1.5, gy = s.truth.position.y / spacing + 1.5;
      CHECK(std::abs(gx - std::round(gx)) < 1e-6);
      CHECK(std::abs(gy - std::round(gy)) < 1e-6);
      CHECK((std::abs(s.truth.position.z - 3.0) < 0.5 || std::abs(s.truth.position.z) < 0.5));  // letter or tile
      CHECK(std::abs(r.position.x - s.truth.position.x) <= pos_tol);
      CHECK(std::abs(r.position.z - s.truth.position.z) <= pos_tol);
      CHECK(degrees(r.normal, s.truth.normal) <= normal_tol);
      const Sample& t = data.test.samples[i];
      CHECK(t.object == s.object);
      CHECK(glm::length(t.truth.position - s.truth.position) < 1.0);
      differs += t.reading.pressure != r.pressure;
    }
    CHECK(differs == data.train.samples.size());  // test readings are new readings of the same poses
  }
}

TEST_CASE("calibration: pressure is stiffness times penetration, spread blurs a step") {
  auto dir = test::temp_dir("sim-calibration");
  auto file = test::write_gltf(plane_mesh(100), dir / "plane.gltf");
  sim::ObjectGeometry geom(sim::load_mesh(file));
  SkinModel skin;
  skin.stiffness_kpa_per_mm = 150;
  sim::TactileSensor sensor(geom, SensorSpec{}, skin);
  for (double depth : {0.0, 0.1, 0.37, 1.5}) {
    auto img = sensor.touch({{0, 0, -depth}, {0, 0, 1}, {1, 0, 0}});
    for (float p : img.pressure) CHECK(p == Approx(150.0 * depth).margin(1e-3));
    CHECK(img.contacts == (150.0 * depth > skin.contact_threshold_kpa ? 36 : 0));
  }
  // Half of the array over a 1 mm step: the elastic layer spreads the edge
  // over neighbouring columns; without spread the columns are sharp.
  auto step = test::write_gltf(test::box_mesh({-50, -50, -50}, {0, 50, 0}), dir / "step.gltf");
  sim::ObjectGeometry block(sim::load_mesh(step));
  for (double spread : {0.0, 1.0}) {
    skin.spread_mm = spread;
    sim::TactileSensor s(block, SensorSpec{}, skin);
    auto img = s.touch({{0, 0, -0.2}, {0, 0, 1}, {1, 0, 0}});
    // Columns 0-2 lie over the block (x < 0), 3-5 over nothing.
    INFO("spread " << spread);
    if (spread == 0.0) {
      CHECK(img.pressure[0] == Approx(30.0).margin(1e-3));
      CHECK(img.pressure[2] == Approx(30.0).margin(1e-3));
      CHECK(img.pressure[3] == Approx(0.0).margin(1e-6));
    } else {
      CHECK(img.pressure[0] == Approx(30.0).epsilon(0.01));
      CHECK(img.pressure[2] < 29.0);
      CHECK(img.pressure[3] > 1.0);
      CHECK(img.pressure[2] + img.pressure[3] == Approx(30.0).epsilon(0.05));  // the spread conserves load
    }
  }
}
