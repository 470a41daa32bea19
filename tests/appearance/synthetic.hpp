#pragma once
// Small synthetic training sets built in code, so the appearance tests do not
// depend on the simulator: readings on spheres around each object's origin,
// with Gaussian-blob pressure images whose shape depends on where they were
// taken (spatially varying appearance) and on a random sensor rotation.
#include <sva/dataset.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <sva/base/rng.hpp>

namespace sva::test {

inline Scene synthetic_scene(int objects) {
  Scene s;
  s.name = "synthetic";
  for (int o = 0; o < objects; ++o) {
    SceneObject so;
    so.name = "obj" + std::to_string(o);
    so.mesh = "/nonexistent/obj" + std::to_string(o) + ".glb";
    s.objects.push_back(so);
  }
  s.appearance.descriptor = "mnti";
  s.appearance.clusters = 6;
  s.appearance.dist_bins = 12;
  s.appearance.dist_min_mm = 5.0;
  s.appearance.dist_max_mm = 80.0;
  return s;
}

// A blob of the given shape, rotated by `angle` and offset by (ox, oy) elements.
inline std::vector<float> blob_image(const SensorSpec& sensor, double sx, double sy, double angle, double ox, double oy,
                                     double peak = 30.0) {
  std::vector<float> img(static_cast<std::size_t>(sensor.elements()));
  const double c = std::cos(angle), s = std::sin(angle);
  for (int r = 0; r < sensor.rows; ++r)
    for (int col = 0; col < sensor.cols; ++col) {
      const double x = col - 0.5 * (sensor.cols - 1) - ox, y = r - 0.5 * (sensor.rows - 1) - oy;
      const double u = c * x + s * y, v = -s * x + c * y;
      img[static_cast<std::size_t>(r * sensor.cols + col)] =
          static_cast<float>(peak * std::exp(-0.5 * (u * u / (sx * sx) + v * v / (sy * sy))));
    }
  return img;
}

inline Dataset synthetic_dataset(int objects, int per_object, std::uint64_t seed = 7) {
  Dataset d;
  d.scene = synthetic_scene(objects);
  d.split = "train";
  d.seed = seed;
  const double shapes[4][2] = {{3.0, 3.0}, {0.8, 3.5}, {1.5, 2.5}, {0.9, 1.0}};
  for (int o = 0; o < objects; ++o)
    for (int i = 0; i < per_object; ++i) {
      util::Rng rng(seed, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
      const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2 * std::numbers::pi);
      const double rho = std::sqrt(1 - z * z);
      const glm::dvec3 n{rho * std::cos(phi), rho * std::sin(phi), z};
      Sample s;
      s.object = static_cast<std::uint32_t>(o);
      s.reading.position = (30.0 + 5.0 * o) * n;
      s.reading.normal = n;
      s.reading.x_axis =
          glm::normalize(glm::cross(n, std::fabs(n.z) < 0.9 ? glm::dvec3{0, 0, 1} : glm::dvec3{1, 0, 0}));
      // Texture bands along z, skewed differently per object, so the objects
      // differ in where each texture is and (for the baseline) how much of it.
      const int texture = std::min(3, static_cast<int>(std::floor(std::pow((z + 1.0) / 2.0, o + 1) * 4.0)));
      s.reading.pressure =
          blob_image(d.scene.sensor, shapes[texture][0], shapes[texture][1], rng.uniform(0.0, 2 * std::numbers::pi),
                     rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
      d.samples.push_back(s);
    }
  return d;
}

}  // namespace sva::test
