// The data-collection protocols of the paper: paper3d (Sec 5.1: random surface
// points, tilted approach, controller until convergence) and letters2d
// (Sec 5.2: a grid of planar poses pressed straight down). Every reading draws
// from its own random stream (seed, split, object, index), so datasets are the
// same bytes whatever the thread count.
#include <sva/error.hpp>
#include <sva/sim/simulate.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <sva/base/float_environment.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/progress.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

namespace sva::sim {

namespace {

constexpr std::uint64_t kTrainStream = 1, kTestStream = 2;

void basis(const glm::dvec3& n, glm::dvec3& t1, glm::dvec3& t2) {
  glm::dvec3 h = std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  t1 = glm::normalize(glm::cross(h, n));
  t2 = glm::cross(n, t1);
}

// A surface point the sensor can approach: nothing of the object lies within
// the approach distance along its normal (this skips faces buried inside
// overlapping parts and turns normals of inside-out triangles around).
void accessible_point(const ObjectGeometry& g, util::Rng& rng, double clearance, glm::dvec3& p, glm::dvec3& n) {
  for (int attempt = 0; attempt < 64; ++attempt) {
    // Drawn in statements, last argument first: the order x86-64's GCC evaluated the call's arguments in, which
    // C++ leaves unspecified and aarch64's GCC reversed (every touch of a dataset differed: issue 54).
    const double u2 = rng.uniform(), u1 = rng.uniform(), u0 = rng.uniform();
    g.sample_surface(u0, u1, u2, p, n);
    if (!g.intersect(p, n, 1e-3, clearance).hit) return;
    if (!g.intersect(p, -n, 1e-3, clearance).hit) {
      n = -n;
      return;
    }
  }
  // A surface with no accessible point in 64 tries: keep the last one; the
  // controller will flag the reading if it cannot converge there.
}

struct Job {
  std::uint64_t stream;
  std::uint32_t object;
  std::uint32_t index;
};

// The controller of a protocol: the scene's budget; the guarded move gives up
// where the rays stop looking.
ControllerSettings controller_settings(const TactileSensor& sensor, const Scene& scene) {
  ControllerSettings cs;
  cs.max_iterations = scene.protocol.max_iterations;
  cs.max_approach_mm = sensor.reach_mm();
  return cs;
}

// The settled contact as the robot reports it (the arm's pose error on the
// reading), with the truth beside it.
Sample report(const Contact& c, const ErrorModel& errors, std::uint64_t arm_seed, std::uint32_t object) {
  Sample s;
  s.reading = c.reading;
  s.object = object;
  s.truth = {c.reading.position, c.reading.normal, c.reading.x_axis, c.surface_normal};
  report_pose(errors, arm_seed, s.reading.position, s.reading.normal, s.reading.x_axis);
  return s;
}

Sample paper3d_reading(const TactileSensor& sensor, const Scene& scene, std::uint64_t seed, const Job& job) {
  const auto& pr = scene.protocol;
  util::Rng rng(seed, job.stream, job.object, job.index);
  glm::dvec3 p, n;
  accessible_point(sensor.object(), rng, pr.approach_mm + TactileSensor::kRayHeadroomMm, p, n);
  glm::dvec3 t1, t2;
  basis(n, t1, t2);
  const double tilt = pr.tilt_deg * M_PI / 180.0 * rng.uniform();
  const double phi = 2.0 * M_PI * rng.uniform();
  SensorPose start;
  start.normal = glm::normalize(so3::rotate(n, tilt, pmath::cos(phi) * t1 + pmath::sin(phi) * t2));
  basis(start.normal, t1, t2);
  const double psi = 2.0 * M_PI * rng.uniform();  // rotation about the normal is not controlled
  start.x_axis = pmath::cos(psi) * t1 + pmath::sin(psi) * t2;
  start.position = p + pr.approach_mm * n;
  const Contact c = press(sensor, start, controller_settings(sensor, scene), util::splitmix64(rng.next()));
  return report(c, scene.errors, util::splitmix64(rng.next()), job.object);
}

Sample letters2d_reading(const TactileSensor& sensor, const Scene& scene, std::uint64_t seed, const Job& job) {
  const auto& pr = scene.protocol;
  const int poses = pr.grid * pr.grid * pr.orientations;
  const int q = static_cast<int>(job.index % static_cast<std::uint32_t>(poses));
  const int a = q % pr.orientations, cell = q / pr.orientations;
  const int i = cell / pr.grid, j = cell % pr.grid;
  util::Rng rng(seed, job.stream, job.object, job.index);
  double x = (j - 0.5 * (pr.grid - 1)) * pr.grid_spacing_mm;
  double y = (i - 0.5 * (pr.grid - 1)) * pr.grid_spacing_mm;
  double angle = 2.0 * M_PI * a / pr.orientations;
  // Test readings (and training readings beyond one per pose) are the same
  // poses placed again: a tiny positioning jitter, and their own noise stream.
  if (job.stream != kTrainStream || static_cast<int>(job.index) >= poses) {
    x += 0.1 * rng.normal();
    y += 0.1 * rng.normal();
    angle += 0.5 * M_PI / 180.0 * rng.normal();
  }
  const Mesh& mesh = sensor.object().mesh();
  SensorPose start;
  start.normal = {0, 0, 1};
  start.x_axis = {pmath::cos(angle), pmath::sin(angle), 0.0};
  start.position = {x, y, mesh.bounds_max.z + pr.approach_mm};
  ControllerSettings cs = controller_settings(sensor, scene);
  cs.reorient = false;  // the letters are pressed flat against the array
  cs.recenter = false;
  const Contact c = press(sensor, start, cs, util::splitmix64(rng.next()));
  return report(c, scene.errors, util::splitmix64(rng.next()), job.object);
}

}  // namespace

ErrorModel scale_errors(const ErrorModel& errors, double factor) {
  auto fmt = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (!std::isfinite(factor) || factor < 0)
    throw Error("error scale " + fmt(factor) + ": must be a finite number >= 0 (0: the ideal world)");
  ErrorModel e = errors;
  for (double* v : {&e.position_sigma_mm, &e.normal_sigma_deg, &e.gain_spread, &e.offset_kpa, &e.noise_kpa,
                    &e.crosstalk, &e.crosstalk_diagonal})
    *v *= factor;
  if (factor == 0) e.full_scale_kpa = 0;
  // The same limits as the scene file's errors block (docs/scene-format.md); the tolerance keeps a product that
  // rounds just above a limit (0.05 x 6) inside it.
  constexpr double kRound = 1e-12;
  if (e.gain_spread > 0.3 + kRound)
    throw Error("error scale " + fmt(factor) + ": the gain spread becomes " + fmt(e.gain_spread) +
                ", above 0.3 (gains would reach 0 at 3 sigma)");
  if (4.0 * (e.crosstalk + e.crosstalk_diagonal) >= 1.0 - kRound)
    throw Error("error scale " + fmt(factor) + ": the crosstalk becomes " + fmt(e.crosstalk) + " + " +
                fmt(e.crosstalk_diagonal) + " (diagonal); the 8 neighbours would read the element's own pressure");
  return e;
}

SimulatedData simulate(const Scene& scene_as_written, const SimulateOptions& options) {
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  Scene scene = scene_as_written;
  scene.errors = scale_errors(scene_as_written.errors, options.error_scale);
  if (scene.objects.empty()) throw Error("scene \"" + scene.name + "\" has no objects");
  const auto& pr = scene.protocol;
  const bool letters = pr.kind == "letters2d";
  if (!letters && pr.kind != "paper3d")
    throw Error("scene \"" + scene.name + "\": unknown protocol \"" + pr.kind + "\"");
  const int per_pose = pr.grid * pr.grid * pr.orientations;
  const int train_n =
      options.train_per_object >= 0 ? options.train_per_object : (letters ? per_pose : pr.train_per_object);
  const int test_n = options.test_per_object >= 0 ? options.test_per_object : (letters ? per_pose : pr.test_per_object);

  // Every mesh is loaded and validated before any work starts. Training and
  // test readings are taken with their own physical sensor (the scene's
  // sensor instance seeds; the same seed is the same sensor).
  std::vector<std::unique_ptr<ObjectGeometry>> geometry;
  std::vector<std::unique_ptr<TactileSensor>> train_sensors, test_sensors;
  const double reach = pr.approach_mm + 10.0;
  for (const auto& o : scene.objects) {
    geometry.push_back(std::make_unique<ObjectGeometry>(load_object_mesh(o)));
    train_sensors.push_back(std::make_unique<TactileSensor>(*geometry.back(), scene.sensor, scene.skin, reach,
                                                            scene.errors, scene.errors.train_sensor));
    test_sensors.push_back(std::make_unique<TactileSensor>(*geometry.back(), scene.sensor, scene.skin, reach,
                                                           scene.errors, scene.errors.test_sensor));
  }

  std::vector<Job> jobs;
  for (std::uint64_t stream : {kTrainStream, kTestStream}) {
    const int n = stream == kTrainStream ? train_n : test_n;
    for (std::uint32_t o = 0; o < scene.objects.size(); ++o)
      for (int k = 0; k < n; ++k) jobs.push_back({stream, o, static_cast<std::uint32_t>(k)});
  }
  std::vector<Sample> samples(jobs.size());
  util::Progress progress("simulate " + scene.name, jobs.size());
  util::parallel_for(
      jobs.size(),
      [&](std::size_t i) {
        const Job& job = jobs[i];
        const TactileSensor& s = job.stream == kTrainStream ? *train_sensors[job.object] : *test_sensors[job.object];
        samples[i] =
            letters ? letters2d_reading(s, scene, options.seed, job) : paper3d_reading(s, scene, options.seed, job);
        progress.advance();
      },
      options.threads);
  progress.finish();

  SimulatedData out;
  out.train.scene = out.test.scene = scene;
  out.train.split = "train";
  out.test.split = "test";
  out.train.seed = out.test.seed = options.seed;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    Dataset& d = jobs[i].stream == kTrainStream ? out.train : out.test;
    d.samples.push_back(std::move(samples[i]));
  }
  return out;
}

}  // namespace sva::sim
