// Writes a synthetic training dataset shaped like the paper's 3D one (objects
// of 80 mm, readings spread over their surface, 6 x 6 images), for
// benchmarking `sva train` when the simulator's data is not at hand:
//   map_synthetic OUT.svad [objects=10] [per_object=1100] [seed=1]
// Objects are ellipsoids; the pressure image is a Gaussian blob whose shape
// depends on where on the surface it was taken (6 textures) and whose
// in-plane rotation is random, as with the real contact controller.
#include <sva/dataset.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include <sva/base/rng.hpp>

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: map_synthetic OUT.svad [objects=10] [per_object=1100] [seed=1]\n");
    return 2;
  }
  const int objects = argc > 2 ? std::atoi(argv[2]) : 10;
  const int per_object = argc > 3 ? std::atoi(argv[3]) : 1100;
  const std::uint64_t seed = argc > 4 ? std::strtoull(argv[4], nullptr, 10) : 1;
  sva::Dataset d;
  d.scene.name = "synthetic-paper3d";
  for (int o = 0; o < objects; ++o) {
    sva::SceneObject so;
    so.name = "ellipsoid" + std::to_string(o);
    so.mesh = "/synthetic/" + so.name + ".glb";
    d.scene.objects.push_back(so);
  }
  d.split = "train";
  d.seed = seed;
  const double shapes[6][2] = {{3.0, 3.0}, {0.8, 3.5}, {1.5, 2.5}, {0.9, 1.0}, {2.0, 0.6}, {1.2, 1.8}};
  const auto& sensor = d.scene.sensor;
  for (int o = 0; o < objects; ++o) {
    const glm::dvec3 axes{40.0, 20.0 + 2.0 * o, 12.0 + 2.5 * o};
    for (int i = 0; i < per_object; ++i) {
      sva::util::Rng rng(seed, static_cast<std::uint64_t>(o), static_cast<std::uint64_t>(i));
      const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2 * std::numbers::pi);
      const double rho = std::sqrt(1 - z * z);
      const glm::dvec3 u{rho * std::cos(phi), rho * std::sin(phi), z};
      const glm::dvec3 p = u * axes;
      const glm::dvec3 n = glm::normalize(u / axes);
      sva::Sample s;
      s.object = static_cast<std::uint32_t>(o);
      s.reading.position = p;
      s.reading.normal = n;
      s.reading.x_axis =
          glm::normalize(glm::cross(n, std::fabs(n.z) < 0.9 ? glm::dvec3{0, 0, 1} : glm::dvec3{1, 0, 0}));
      const int texture = (o + static_cast<int>(std::floor((p.x / 40.0 + 1.0) * 1.5)) + (p.z > 0 ? 3 : 0)) % 6;
      const double angle = rng.uniform(0.0, 2 * std::numbers::pi), ox = rng.uniform(-0.5, 0.5),
                   oy = rng.uniform(-0.5, 0.5);
      const double c = std::cos(angle), sn = std::sin(angle);
      s.reading.pressure.resize(static_cast<std::size_t>(sensor.elements()));
      for (int r = 0; r < sensor.rows; ++r)
        for (int col = 0; col < sensor.cols; ++col) {
          const double x = col - 0.5 * (sensor.cols - 1) - ox, y = r - 0.5 * (sensor.rows - 1) - oy;
          const double a = c * x + sn * y, b = -sn * x + c * y;
          const double v = 30.0 * std::exp(-0.5 * (a * a / (shapes[texture][0] * shapes[texture][0]) +
                                                   b * b / (shapes[texture][1] * shapes[texture][1]))) +
                           rng.normal() * 0.3;
          s.reading.pressure[static_cast<std::size_t>(r * sensor.cols + col)] = static_cast<float>(std::max(0.0, v));
        }
      d.samples.push_back(std::move(s));
    }
  }
  sva::save_dataset(d, argv[1]);
  std::printf("%s: %zu synthetic readings of %d objects\n", argv[1], d.samples.size(), objects);
  return 0;
} catch (const sva::Error& e) {
  std::fprintf(stderr, "map_synthetic: %s\n", e.what());
  return 1;
}
