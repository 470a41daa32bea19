#pragma once
// A public sva::Map trained by the map builder from a small synthetic dataset
// with pressure images (the fixture's ellipsoids, each point's class drawn as
// a blob shape), and readings of it: for tests of the public recognizer API.
#include <sva/dataset.hpp>
#include <sva/map.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include "fixture.hpp"

namespace sva::test {

// A blob image whose shape is the point's texture, rotated at random about the
// normal (the controllers leave that rotation free).
inline std::vector<float> texture_image(const SensorSpec& sensor, std::uint32_t texture, double angle) {
  const double shapes[4][2] = {{3.0, 3.0}, {0.8, 3.5}, {1.5, 2.5}, {0.9, 1.0}};
  const double sx = shapes[texture % 4][0], sy = shapes[texture % 4][1];
  std::vector<float> img(static_cast<std::size_t>(sensor.elements()));
  const double c = std::cos(angle), s = std::sin(angle);
  for (int r = 0; r < sensor.rows; ++r)
    for (int col = 0; col < sensor.cols; ++col) {
      const double x = col - 0.5 * (sensor.cols - 1), y = r - 0.5 * (sensor.rows - 1);
      const double u = c * x + s * y, v = -s * x + c * y;
      img[static_cast<std::size_t>(r * sensor.cols + col)] =
          static_cast<float>(30.0 * std::exp(-0.5 * (u * u / (sx * sx) + v * v / (sy * sy))));
    }
  return img;
}

inline Reading reading_of(const SensorSpec& sensor, const WorldPoint& w, const RigidPose& pose, util::Rng& rng) {
  Reading r;
  r.position = pose.apply(w.p);
  r.normal = pose.rotate(w.n);
  r.x_axis =
      glm::normalize(glm::cross(r.normal, std::fabs(r.normal.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  r.pressure = texture_image(sensor, w.cls, rng.uniform(0.0, 2.0 * std::numbers::pi));
  return r;
}

// An empty training set of the synthetic world: `objects` objects named prefix0, prefix1, ... with no mesh, and
// the appearance settings the synthetic textures need (mnti, 4 classes, 12 distance bins over 5-80 mm).
inline Dataset synthetic_training_set(const std::string& scene, const std::string& prefix, int objects) {
  Dataset d;
  d.scene.name = scene;
  for (int o = 0; o < objects; ++o) {
    SceneObject so;
    so.name = prefix + std::to_string(o);
    so.mesh = "/nonexistent.glb";
    d.scene.objects.push_back(so);
  }
  d.scene.appearance.descriptor = "mnti";
  d.scene.appearance.clusters = 4;
  d.scene.appearance.dist_bins = 12;
  d.scene.appearance.dist_min_mm = 5.0;
  d.scene.appearance.dist_max_mm = 80.0;
  d.split = "train";
  return d;
}

struct Trained {
  WorldSpec spec;
  Dataset data;
  Map map;
};

inline const Trained& trained() {
  static const Trained t = [] {
    Trained x;
    x.spec.classes = 4;
    x.spec.points = 70;
    x.data = synthetic_training_set("synthetic-recognizer", "obj", x.spec.objects);
    for (int o = 0; o < x.spec.objects; ++o)
      for (int i = 0; i < x.spec.points; ++i) {
        util::Rng rng(1, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
        Sample s;
        s.object = static_cast<std::uint32_t>(o);
        s.reading = reading_of(x.data.scene.sensor, world_point(x.spec, o, i), RigidPose{}, rng);
        x.data.samples.push_back(s);
      }
    TrainOptions o;
    o.calibrate = false;  // the recognizer's tests read the belief; the calibration is tests/calibration's
    x.map = Map::train(x.data, o);
    return x;
  }();
  return t;
}

// `count` readings of the synthetic world's `object` at points drawn by `rng`, the object lying at `truth`.
inline std::vector<Reading> readings_at(std::uint32_t object, const RigidPose& truth, util::Rng rng, int count) {
  const Trained& t = trained();
  std::vector<Reading> out;
  for (int i = 0; i < count; ++i)
    out.push_back(reading_of(t.data.scene.sensor,
                             world_point(t.spec, static_cast<int>(object), static_cast<int>(rng.below(70))), truth,
                             rng));
  return out;
}

}  // namespace sva::test
