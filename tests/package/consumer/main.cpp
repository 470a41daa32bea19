// Uses only installed headers: a scene from the installed assets, the
// recognizer's error path for an empty map, and then the whole public path on a
// tiny synthetic dataset: train a map, save it and the test readings to the
// folder given (examples/cpp_recognize reads them), recognise through an Engine.
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>
#include <sva/scene.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

namespace {

// Two spheres of radius 40 whose pressure blobs vary over the surface and between the objects.
sva::Dataset tiny_dataset(const std::string& split, int per_object, double shift) {
  sva::Dataset d;
  d.scene.name = "package-tiny";
  for (const char* name : {"ball", "pebble"}) {
    sva::SceneObject o;
    o.name = name;
    o.mesh = "/nonexistent.glb";
    d.scene.objects.push_back(o);
  }
  d.scene.appearance.clusters = 6;
  d.scene.appearance.dist_bins = 16;
  d.scene.appearance.dist_min_mm = 10.0;
  d.scene.appearance.dist_max_mm = 80.0;
  d.split = split;
  const sva::SensorSpec& sensor = d.scene.sensor;
  for (std::uint32_t object = 0; object < 2; ++object)
    for (int i = 0; i < per_object; ++i) {
      const double z = 1.0 - 2.0 * (i + 0.5) / per_object;
      const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0)) + shift;
      const glm::dvec3 n(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
      sva::Sample s;
      s.object = object;
      s.reading.position = 40.0 * n;
      s.reading.normal = n;
      s.reading.x_axis = glm::normalize(glm::cross(n, std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
      const glm::dvec3 p = s.reading.position;
      const double a = 1.2 + 1.5 * (0.5 + 0.5 * std::sin(p.z / 12.0 + 1.7 * object));
      const double b = 0.7 + 0.8 * (0.5 + 0.5 * std::cos(p.x / 15.0 - object));
      const double th = std::atan2(p.y, p.x);
      for (int r = 0; r < sensor.rows; ++r)
        for (int c = 0; c < sensor.cols; ++c) {
          const double x = (c - (sensor.cols - 1) / 2.0) * sensor.pitch_mm,
                       y = (r - (sensor.rows - 1) / 2.0) * sensor.pitch_mm;
          const double u = std::cos(th) * x + std::sin(th) * y, v = -std::sin(th) * x + std::cos(th) * y;
          s.reading.pressure.push_back(static_cast<float>(30.0 * std::exp(-u * u / (2 * a * a) - v * v / (2 * b * b))));
        }
      d.samples.push_back(s);
    }
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  const sva::Scene scene = sva::load_scene("paper3d");
  if (scene.objects.size() != 10) {
    std::fprintf(stderr, "expected 10 objects in the installed paper3d scene, got %zu\n", scene.objects.size());
    return 1;
  }
  try {
    sva::Recognizer r(sva::Map{}, scene.pose_space);
    std::fprintf(stderr, "an empty map was accepted\n");
    return 1;
  } catch (const sva::Error& e) {
    std::printf("ok: %zu objects; empty map refused: %s\n", scene.objects.size(), e.what());
  }
  if (argc < 2) return 0;
  const std::filesystem::path out = argv[1];
  std::filesystem::create_directories(out);
  sva::TrainOptions options;
  options.threads = 1;
  const sva::Map map = sva::Map::train(tiny_dataset("train", 48, 0.0), options);
  map.save(out / "tiny.svam");
  const sva::Dataset test = tiny_dataset("test", 12, 0.05);
  sva::save_dataset(test, out / "tiny.svad");
  const sva::Engine engine(map);
  sva::Recognizer rec(engine, map.pose_space());
  for (const sva::Sample& s : test.samples)
    if (s.object == 1 && rec.reading_count() < 8) rec.add_reading(s.reading);
  const sva::Estimate e = rec.estimate(2);
  std::printf("ok: engine on %s; recognised %s with p = %.3f, %zu hypotheses\n", engine.backend_description().c_str(),
              e.object_name.c_str(), e.object_probability[e.object], e.hypotheses.size());
  return e.hypotheses.empty() ? 1 : 0;
}
