// The skin model of docs/sensor-model.md: penetration of the object into the
// skin plane, sampled by rays on a sub-element grid, spread by the elastic
// layer (a Gaussian), averaged per element and calibrated to kPa.
#include <sva/error.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>

#include "util/rng.hpp"

namespace sva::sim {

TactileSensor::TactileSensor(const ObjectGeometry& object, const SensorSpec& sensor, const SkinModel& skin,
                             double reach_mm)
    : object_(object), sensor_(sensor), skin_(skin), reach_mm_(reach_mm) {
  if (sensor.rows < 1 || sensor.cols < 1 || !(sensor.pitch_mm > 0))
    throw Error("sensor: rows, cols and pitch must be positive");
  if (skin.rays_per_axis < 1) throw Error("skin: rays_per_axis must be at least 1");
  if (!(skin.stiffness_kpa_per_mm > 0)) throw Error("skin: stiffness must be positive");
  rays_per_axis_ = skin.rays_per_axis;
  const double sub = sensor.pitch_mm / rays_per_axis_;
  const double sigma = skin.spread_mm / sub;  // in sub-samples
  // The kernel reaches 3 sigma; the rays extend that far beyond the array so
  // that the spread at the array's border sees the surface outside it.
  margin_ = sigma > 0 ? static_cast<int>(std::ceil(3.0 * sigma)) : 0;
  kernel_.assign(static_cast<std::size_t>(2 * margin_ + 1), 0.0);
  double total = 0;
  for (int k = -margin_; k <= margin_; ++k) {
    double w = sigma > 0 ? std::exp(-0.5 * (k * k) / (sigma * sigma)) : 1.0;
    kernel_[static_cast<std::size_t>(k + margin_)] = w;
    total += w;
  }
  for (auto& w : kernel_) w /= total;
}

TactileImage TactileSensor::touch(const SensorPose& pose, std::uint64_t noise_seed) const {
  const int r = rays_per_axis_, m = margin_;
  const int ny = sensor_.rows * r + 2 * m, nx = sensor_.cols * r + 2 * m;
  const double sub = sensor_.pitch_mm / r;
  const glm::dvec3 n = pose.normal, x = pose.x_axis, y = glm::cross(pose.normal, pose.x_axis);
  const double H = kRayHeadroomMm;
  const glm::dvec3 down = -n;

  std::vector<double> depth(static_cast<std::size_t>(nx * ny), 0.0);
  TactileImage img;
  double gap = std::numeric_limits<double>::infinity();
  glm::dvec3 normal_sum(0.0);
  thread_local std::vector<glm::dvec3> origins;
  thread_local std::vector<ObjectGeometry::Hit> hits;
  origins.resize(static_cast<std::size_t>(nx * ny));
  for (int a = 0; a < ny; ++a) {
    const double v = (a - m + 0.5) * sub - 0.5 * sensor_.rows * sensor_.pitch_mm;
    for (int b = 0; b < nx; ++b) {
      const double u = (b - m + 0.5) * sub - 0.5 * sensor_.cols * sensor_.pitch_mm;
      origins[static_cast<std::size_t>(a * nx + b)] = pose.position + u * x + v * y + H * n;
    }
  }
  object_.intersect_parallel(origins, down, H + reach_mm_, hits);
  for (int a = 0; a < ny; ++a) {
    const bool row_in = a >= m && a < ny - m;
    for (int b = 0; b < nx; ++b) {
      const ObjectGeometry::Hit& h = hits[static_cast<std::size_t>(a * nx + b)];
      if (!h.hit) continue;
      const double d = std::clamp(H - h.t, 0.0, H);  // penetration into the skin
      depth[static_cast<std::size_t>(a * nx + b)] = d;
      const bool in_array = row_in && b >= m && b < nx - m;
      if (!in_array) continue;
      img.surface_below = true;
      gap = std::min(gap, h.t - H);
      if (d > 0) {
        // The surface faces the sensor where the ray meets it: orient the
        // facet normal towards the ray origin whatever the mesh winding.
        glm::dvec3 fn = glm::dot(h.normal, n) < 0 ? -h.normal : h.normal;
        normal_sum += d * fn;
      }
    }
  }
  img.gap_mm = img.surface_below ? gap : std::numeric_limits<double>::infinity();
  double ns = glm::length(normal_sum);
  img.surface_normal = ns > 0 ? normal_sum / ns : glm::dvec3(0.0);

  // Elastic spread: separable Gaussian, then only the array's samples are kept.
  std::vector<double> tmp(depth.size(), 0.0);
  if (m > 0) {
    for (int a = 0; a < ny; ++a)
      for (int b = m; b < nx - m; ++b) {
        double s = 0;
        for (int k = -m; k <= m; ++k)
          s += kernel_[static_cast<std::size_t>(k + m)] * depth[static_cast<std::size_t>(a * nx + b + k)];
        tmp[static_cast<std::size_t>(a * nx + b)] = s;
      }
    for (int a = m; a < ny - m; ++a)
      for (int b = m; b < nx - m; ++b) {
        double s = 0;
        for (int k = -m; k <= m; ++k)
          s += kernel_[static_cast<std::size_t>(k + m)] * tmp[static_cast<std::size_t>((a + k) * nx + b)];
        depth[static_cast<std::size_t>(a * nx + b)] = s;
      }
  }

  const int elements = sensor_.elements();
  img.pressure.assign(static_cast<std::size_t>(elements), 0.0f);
  util::Rng noise(noise_seed, 0x6e6f697365ull);
  const double inv = 1.0 / (r * r);
  double sum = 0, wsum = 0;
  glm::dvec2 centroid(0.0);
  for (int i = 0; i < sensor_.rows; ++i)
    for (int j = 0; j < sensor_.cols; ++j) {
      double s = 0;
      for (int a = 0; a < r; ++a)
        for (int b = 0; b < r; ++b) s += depth[static_cast<std::size_t>((m + i * r + a) * nx + (m + j * r + b))];
      double p = skin_.stiffness_kpa_per_mm * s * inv;
      if (skin_.noise_kpa > 0) p += skin_.noise_kpa * noise.normal();
      p = std::max(p, 0.0);
      float pf = static_cast<float>(p);
      img.pressure[static_cast<std::size_t>(i * sensor_.cols + j)] = pf;
      if (pf > skin_.contact_threshold_kpa) {
        ++img.contacts;
        sum += pf;
        wsum += pf;
        centroid += static_cast<double>(pf) * glm::dvec2((j - 0.5 * (sensor_.cols - 1)) * sensor_.pitch_mm,
                                                         (i - 0.5 * (sensor_.rows - 1)) * sensor_.pitch_mm);
      }
    }
  if (img.contacts > 0) {
    img.mean_contact_kpa = sum / img.contacts;
    img.contact_centroid = centroid / wsum;
  }
  return img;
}

}  // namespace sva::sim
