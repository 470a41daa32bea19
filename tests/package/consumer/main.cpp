// Uses only installed headers: a scene from the installed assets, the
// recognizer's error path for an empty map, and then the whole public path on a
// tiny synthetic dataset: train a map, save it and the test readings to the
// folder given (examples/cpp_recognize reads them), recognise through an Engine, and recognise a sessions file
// (batch recognition is the engine library's: a robot links nothing else).
#include <sva/batch_file.hpp>
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
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

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
  if (e.hypotheses.empty()) return 1;
  // A sessions file of one session per object (4 readings each), checked whole and recognised into a results file.
  std::vector<sva::BatchSession> sessions{{"ball", {}, ""}, {"pebble", {}, R"({"object":"pebble"})"}};
  for (const sva::Sample& s : test.samples)
    if (sessions[s.object].readings.size() < 4) sessions[s.object].readings.push_back(s.reading);
  sva::write_batch_sessions(out / "sessions.jsonl", sessions);
  const sva::BatchSessionsFile file(out / "sessions.jsonl", map.sensor().elements());
  sva::BatchRecognizer batch(engine, map.pose_space(), file.sessions());
  file.recognize(batch, map, out / "results.jsonl");
  std::ifstream results(out / "results.jsonl");
  std::size_t lines = 0;
  for (std::string line; std::getline(results, line);) lines += line.find("\"id\":\"") != std::string::npos ? 1 : 0;
  std::printf("ok: %zu sessions of %zu readings recognised into %zu result lines\n", file.sessions(), file.readings(),
              lines);
  return lines == 2 ? 0 : 1;
}
