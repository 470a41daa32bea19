// The scene's error model and the controller that steers by the array alone:
// the statistics of the reported pose against the truth, one physical sensor's
// fixed gains, saturation, crosstalk, frame noise, the guarded move, and where
// the plane-fit controller leaves the sensor.
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/sim/sensor_errors.hpp>
#include <sva/sim/simulate.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>

#include "gltf_writer.hpp"
#include "test_support.hpp"

using namespace sva;

namespace {

double degrees(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / M_PI;
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// An element's position in a row-major 6 x 6 image.
std::size_t at(int row, int col) { return static_cast<std::size_t>(row * 6 + col); }

ErrorModel only_array(double gain, double offset, double noise) {
  ErrorModel e;
  e.gain_spread = gain;
  e.offset_kpa = offset;
  e.noise_kpa = noise;
  return e;
}

sim::ObjectGeometry plane_geometry(const std::string& name) {
  test::TestMesh m;
  m.positions = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return sim::ObjectGeometry(sim::load_mesh(test::write_gltf(m, test::temp_dir(name) / "plane.gltf")));
}

// The tiny scene with more readings: what the statistics below are taken over.
const sim::SimulatedData& tiny_data() {
  static const sim::SimulatedData data = [] {
    sim::SimulateOptions opt;
    opt.train_per_object = 100;
    opt.test_per_object = 50;
    opt.seed = test::scenario_seed(3);
    return sim::simulate(load_scene("tiny"), opt);
  }();
  return data;
}

}  // namespace

TEST_CASE("errors: the reported pose of tiny's readings is off the truth by the configured sigmas") {
  const auto& data = tiny_data();
  const ErrorModel& e = data.train.scene.errors;
  REQUIRE(e.position_sigma_mm > 0);
  REQUIRE(e.normal_sigma_deg > 0);
  std::vector<double> dp, dn, dx;
  for (const auto* d : {&data.train, &data.test})
    for (const Sample& s : d->samples) {
      const glm::dvec3 diff = s.reading.position - s.truth.position;
      dp.insert(dp.end(), {diff.x, diff.y, diff.z});
      dn.push_back(degrees(s.reading.normal, s.truth.normal));
      // The turn about the normal shows in the x axis once the tilt is taken out.
      dx.push_back(degrees(s.reading.x_axis, s.truth.x_axis));
      CHECK(std::abs(glm::length(s.reading.normal) - 1.0) < 1e-9);
      CHECK(std::abs(glm::dot(s.reading.normal, s.reading.x_axis)) < 1e-9);
    }
  REQUIRE(dp.size() == 900u);
  // 900 position errors: the sample sigma is within 10% of the true one with
  // a margin of over 4 standard errors.
  CHECK(rms(dp) == Approx(e.position_sigma_mm).epsilon(0.10));
  // The rotation vector has sigma per axis; the normal tilts by its two
  // components across the normal: a Rayleigh angle with RMS sigma * sqrt(2).
  CHECK(rms(dn) == Approx(e.normal_sigma_deg * std::sqrt(2.0)).epsilon(0.12));
  CHECK(rms(dx) > 0.5 * e.normal_sigma_deg);
}

TEST_CASE("errors: report_pose is exact with zero sigmas and unbiased with errors") {
  glm::dvec3 p(1, 2, 3), n(0, 0, 1), x(1, 0, 0);
  sim::report_pose(ErrorModel{}, 5, p, n, x);
  CHECK(p == glm::dvec3(1, 2, 3));
  CHECK(n == glm::dvec3(0, 0, 1));
  CHECK(x == glm::dvec3(1, 0, 0));
  ErrorModel e;
  e.position_sigma_mm = 2.0;
  e.normal_sigma_deg = 1.0;
  glm::dvec3 mean(0.0);
  std::vector<double> tilt;
  for (std::uint64_t seed = 0; seed < 4000; ++seed) {
    glm::dvec3 q(0.0), m(0, 0, 1), a(1, 0, 0);
    sim::report_pose(e, seed, q, m, a);
    mean += q / 4000.0;
    tilt.push_back(degrees(m, {0, 0, 1}));
  }
  CHECK(glm::length(mean) < 0.15);  // 4 standard errors of the mean of 4000 draws of sigma 2 in 3-D
  CHECK(rms(tilt) == Approx(std::sqrt(2.0)).epsilon(0.05));
  // The same seed is the same error.
  glm::dvec3 q1(0.0), m1(0, 0, 1), a1(1, 0, 0), q2(0.0), m2(0, 0, 1), a2(1, 0, 0);
  sim::report_pose(e, 77, q1, m1, a1);
  sim::report_pose(e, 77, q2, m2, a2);
  CHECK(q1 == q2);
  CHECK(m1 == m2);
}

TEST_CASE("errors: one sensor seed is one set of gains and offsets, two seeds are two sensors") {
  SensorSpec spec;
  spec.rows = spec.cols = 32;  // 1024 elements: enough for the spread's statistics
  const ErrorModel e = only_array(0.05, 0.3, 0.0);
  sim::SensorInstance a(spec, e, 1), again(spec, e, 1), b(spec, e, 2);
  CHECK(a.gains() == again.gains());
  CHECK(a.offsets() == again.offsets());
  CHECK(a.gains() != b.gains());
  CHECK(a.offsets() != b.offsets());
  std::vector<double> g, o;
  for (double x : a.gains()) g.push_back(x - 1.0);
  for (double x : a.offsets()) o.push_back(x);
  CHECK(rms(g) == Approx(0.05).epsilon(0.10));
  CHECK(rms(o) == Approx(0.3).epsilon(0.10));
  // And the reading: a uniform 20 kPa reads gain * 20 + offset.
  std::vector<double> uniform(1024, 20.0);
  const auto img = a.read(uniform, 9);
  for (std::size_t i = 0; i < img.size(); ++i)
    CHECK(img[i] == Approx(a.gains()[i] * 20.0 + a.offsets()[i]).margin(1e-4));
  // An ideal instance reads the truth.
  sim::SensorInstance ideal(spec, ErrorModel{}, 4);
  CHECK(ideal.read(uniform, 9) == std::vector<float>(1024, 20.0f));
}

TEST_CASE("errors: an element saturates at full scale") {
  ErrorModel e;
  e.full_scale_kpa = 150;
  sim::SensorInstance s(SensorSpec{}, e, 1);
  std::vector<double> p(36, 0.0);
  p[0] = 149.0;
  p[1] = 151.0;
  p[2] = 1000.0;
  const auto img = s.read(p, 1);
  CHECK(img[0] == Approx(149.0));
  CHECK(img[1] == Approx(150.0));
  CHECK(img[2] == Approx(150.0));
  // Through the skin: a sensor pressed 3 mm into a plane reads full scale everywhere.
  auto plane = plane_geometry("errors-saturation");
  sim::TactileSensor sensor(plane, SensorSpec{}, SkinModel{}, 13.0, e, 1);
  const auto deep = sensor.touch({{0, 0, -3.0}, {0, 0, 1}, {1, 0, 0}});
  for (float v : deep.pressure) CHECK(v == Approx(150.0));
  const auto shallow = sensor.touch({{0, 0, -1.0}, {0, 0, 1}, {1, 0, 0}});
  for (float v : shallow.pressure) CHECK(v == Approx(100.0).margin(1e-3));
}

TEST_CASE("errors: crosstalk spreads a single-element press to the 4 and the 8 neighbours") {
  for (double diagonal : {0.0, 0.01}) {
    ErrorModel e;
    e.crosstalk = 0.03;
    e.crosstalk_diagonal = diagonal;
    sim::SensorInstance s(SensorSpec{}, e, 1);
    std::vector<double> p(36, 0.0);
    p[at(2, 3)] = 100.0;
    const auto img = s.read(p, 1);
    INFO("diagonal " << diagonal);
    CHECK(img[at(2, 3)] == Approx(100.0));
    for (auto [r, c] : {std::pair{1, 3}, {3, 3}, {2, 2}, {2, 4}}) CHECK(img[at(r, c)] == Approx(3.0));
    for (auto [r, c] : {std::pair{1, 2}, {1, 4}, {3, 2}, {3, 4}}) CHECK(img[at(r, c)] == Approx(100.0 * diagonal));
    double rest = 0;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        if (std::abs(r - 2) > 1 || std::abs(c - 3) > 1) rest += img[at(r, c)];
    CHECK(rest == 0.0);
  }
}

TEST_CASE("errors: frame noise has its sigma, is the same for one frame seed and new for the next") {
  SensorSpec spec;
  spec.rows = spec.cols = 32;
  // The skin's own noise and the error model's add in quadrature.
  sim::SensorInstance s(spec, only_array(0.0, 0.0, 0.4), 1, 0.3);
  std::vector<double> p(1024, 50.0);
  const auto a = s.read(p, 1), again = s.read(p, 1), b = s.read(p, 2);
  CHECK(a == again);
  CHECK(a != b);
  std::vector<double> d;
  for (float v : a) d.push_back(v - 50.0);
  CHECK(rms(d) == Approx(0.5).epsilon(0.10));
}

TEST_CASE("controller: the approach is a guarded move that stops within a step of the contact threshold") {
  auto plane = plane_geometry("errors-guarded");
  SkinModel skin;
  sim::TactileSensor sensor(plane, SensorSpec{}, skin, 13.0);
  sim::ControllerSettings cs;
  cs.max_iterations = 0;  // stop where the guarded move stops
  for (double start : {1.0, 3.05, 7.33}) {
    const auto c = sim::press(sensor, {{0.4, 0.1, start}, {0, 0, 1}, {1, 0, 0}}, cs, 1);
    INFO("start " << start);
    // Contact is when an element reads above the threshold: penetration past
    // threshold / stiffness, by less than one step.
    const double depth = -c.reading.position.z;
    CHECK(depth > skin.contact_threshold_kpa / skin.stiffness_kpa_per_mm);
    CHECK(depth <= skin.contact_threshold_kpa / skin.stiffness_kpa_per_mm + cs.approach_step_mm + 1e-9);
    CHECK(c.reading.status == ControllerStatus::not_converged);
  }
  // Beyond the guarded move's travel nothing is touched.
  cs.max_approach_mm = 2.0;
  const auto far = sim::press(sensor, {{0, 0, 3.0}, {0, 0, 1}, {1, 0, 0}}, cs, 1);
  CHECK(far.reading.status == ControllerStatus::no_contact);
  CHECK(far.reading.position.z == Approx(1.0));
}

TEST_CASE("controller: on a plane it settles where its plane fit says the surface is, not exactly on it") {
  auto plane = plane_geometry("errors-settle");
  const ErrorModel real = load_scene("tiny").errors;
  sim::ControllerSettings cs;
  int nonzero = 0, runs = 0;
  for (int with_errors = 0; with_errors < 2; ++with_errors)
    for (std::uint64_t sensor_seed = 1; sensor_seed <= 3; ++sensor_seed) {
      sim::TactileSensor sensor(plane, SensorSpec{}, SkinModel{}, 13.0, with_errors ? real : ErrorModel{}, sensor_seed);
      for (double tilt : {0.7, 1.5, 4.0, 6.0, 10.0}) {
        const double t = tilt * M_PI / 180;
        const sim::SensorPose start{
            {0.3, -0.2, 3.0}, {std::sin(t), 0.0, std::cos(t)}, {std::cos(t), 0.0, -std::sin(t)}};
        const auto c = sim::press(sensor, start, cs, 11 + sensor_seed);
        INFO("errors " << with_errors << " sensor " << sensor_seed << " tilt " << tilt);
        REQUIRE(c.reading.status == ControllerStatus::converged);
        const double settled = degrees(c.reading.normal, c.surface_normal);
        CHECK(degrees(c.surface_normal, {0, 0, 1}) < 1e-6);  // the truth the rays report
        // The model: the controller stops once the plane fitted to its image
        // tilts by at most the tolerance, so the sensor stays tilted by what
        // that fit still sees. On a plane in full contact the fit is exact for
        // an ideal array; an array's gain, offset and noise move it by about
        // sigma / (stiffness * sqrt(sum x^2)) = 1.1 kPa / (100 kPa/mm * 20.5 mm)
        // = 0.03 degrees per axis.
        const glm::dvec3 f = sim::fit_contact_plane(c.reading.pressure, SensorSpec{}, SkinModel{});
        const double fitted = std::atan2(std::hypot(f.x, f.y), f.z) * 180.0 / M_PI;
        CHECK(fitted <= cs.normal_tolerance_deg);
        CHECK(settled == Approx(fitted).margin(with_errors ? 0.15 : 0.01));
        nonzero += settled > 0.01;
        ++runs;
      }
    }
  // A tilted start is not finished exactly on the surface: the first fits see a
  // partial contact whose edge the skin's spread flattens, so they under-turn.
  CHECK(nonzero >= 3 * runs / 4);
}

TEST_CASE("controller: converges on tiny's objects with errors on, settling near, not on, the true normal") {
  const auto& data = tiny_data();
  std::size_t converged = 0;
  std::vector<double> settled;
  for (const Sample& s : data.train.samples) {
    if (s.reading.status != ControllerStatus::converged) continue;
    ++converged;
    REQUIRE(glm::length(s.truth.surface_normal) == Approx(1.0));
    settled.push_back(degrees(s.truth.normal, s.truth.surface_normal));
  }
  const double share = static_cast<double>(converged) / static_cast<double>(data.train.samples.size());
  test::margin("tiny: share of training contacts converged", share, ">=", 0.95);
  CHECK(share >= 0.95);
  // The true surface normal is the penetration-weighted facet normal under the
  // array; the controller settles on the plane its image fits, which on the
  // die's pips and the brick's studs is near it but not on it.
  test::margin("tiny: median settled normal off the surface's (deg), low", median(settled), ">", 0.05);
  test::margin("tiny: median settled normal off the surface's (deg), high", median(settled), "<",
               sim::ControllerSettings{}.normal_tolerance_deg);
  CHECK(median(settled) > 0.05);
  CHECK(median(settled) < sim::ControllerSettings{}.normal_tolerance_deg);
}

TEST_CASE("errors: the train and test splits are read by their own sensor") {
  Scene scene = load_scene("tiny");
  scene.objects.resize(1);
  sim::SimulateOptions opt;
  opt.train_per_object = 3;
  opt.test_per_object = 3;
  // The same seeds for both splits, and only the gains differ: the same poses
  // and noise, read through another sensor's gains when the instances differ.
  scene.errors = only_array(0.05, 0.0, 0.0);
  scene.errors.train_sensor = scene.errors.test_sensor = 5;
  auto same = sim::simulate(scene, opt);
  scene.errors.test_sensor = 6;
  auto other = sim::simulate(scene, opt);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(same.train.samples[i].reading.pressure == other.train.samples[i].reading.pressure);
    CHECK(same.test.samples[i].reading.pressure != other.test.samples[i].reading.pressure);
  }
}
