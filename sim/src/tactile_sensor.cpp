// The skin model of docs/sensor-model.md: penetration of the object into the
// skin plane, sampled by rays on a sub-element grid, spread by the elastic
// layer (a Gaussian), averaged per element and calibrated to kPa; then read
// by one physical array (sensor_errors.hpp).
#include <sva/error.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>
#include <sva/base/portable_math.hpp>

namespace sva::sim {

namespace {
const SensorSpec& checked(const SensorSpec& sensor) {
  if (sensor.rows < 1 || sensor.cols < 1 || !(sensor.pitch_mm > 0))
    throw Error("sensor: rows, cols and pitch must be positive");
  return sensor;
}
}  // namespace

TactileSensor::TactileSensor(const ObjectGeometry& object, const SensorSpec& sensor, const SkinModel& skin,
                             double reach_mm, const ErrorModel& errors, std::uint64_t instance_seed)
    : object_(object),
      sensor_(sensor),
      skin_(skin),
      reach_mm_(reach_mm),
      instance_(checked(sensor), errors, instance_seed, skin.noise_kpa) {
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
    double w = sigma > 0 ? pmath::exp(-0.5 * (k * k) / (sigma * sigma)) : 1.0;
    kernel_[static_cast<std::size_t>(k + margin_)] = w;
    total += w;
  }
  for (auto& w : kernel_) w /= total;
}

TactileImage TactileSensor::touch(const SensorPose& pose, std::uint64_t frame_seed) const {
  const int r = rays_per_axis_, m = margin_;
  const int ny = sensor_.rows * r + 2 * m, nx = sensor_.cols * r + 2 * m;
  const double sub = sensor_.pitch_mm / r;
  const glm::dvec3 n = pose.normal, x = pose.x_axis, y = glm::cross(pose.normal, pose.x_axis);
  const double H = kRayHeadroomMm;
  const glm::dvec3 down = -n;

  std::vector<double> depth(static_cast<std::size_t>(nx * ny), 0.0);
  TactileImage img;
  double clearance = reach_mm_;
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
      clearance = std::min(clearance, h.t - H);
      const double d = std::clamp(H - h.t, 0.0, H);  // penetration into the skin
      depth[static_cast<std::size_t>(a * nx + b)] = d;
      if (d > 0 && row_in && b >= m && b < nx - m) {
        // The surface faces the sensor where the ray meets it: orient the
        // facet normal towards the ray origin whatever the mesh winding.
        glm::dvec3 fn = glm::dot(h.normal, n) < 0 ? -h.normal : h.normal;
        normal_sum += d * fn;
      }
    }
  }
  img.clearance_mm = clearance;
  double ns = glm::length(normal_sum);
  img.surface_normal = ns > 0 ? normal_sum / ns : glm::dvec3(0.0);
  depth = spread(std::move(depth), nx, ny);

  // Element depth -> physical pressure -> what the array reports.
  std::vector<double> physical(static_cast<std::size_t>(sensor_.elements()), 0.0);
  const double inv = 1.0 / (r * r);
  for (int i = 0; i < sensor_.rows; ++i)
    for (int j = 0; j < sensor_.cols; ++j) {
      double s = 0;
      for (int a = 0; a < r; ++a)
        for (int b = 0; b < r; ++b) s += depth[static_cast<std::size_t>((m + i * r + a) * nx + (m + j * r + b))];
      physical[static_cast<std::size_t>(i * sensor_.cols + j)] = skin_.stiffness_kpa_per_mm * s * inv;
    }
  img.pressure = instance_.read(physical, frame_seed);
  summarise(img);
  return img;
}

TactileImage TactileSensor::untouched(std::uint64_t frame_seed) const {
  TactileImage img;
  img.pressure = instance_.read(std::vector<double>(static_cast<std::size_t>(sensor_.elements()), 0.0), frame_seed);
  summarise(img);
  return img;
}

// Elastic spread: separable Gaussian; only the array's samples are kept.
std::vector<double> TactileSensor::spread(std::vector<double> depth, int nx, int ny) const {
  const int m = margin_;
  if (m == 0) return depth;
  std::vector<double> tmp(depth.size(), 0.0);
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
  return depth;
}

// What the controller reads off a reported image: the elements in contact,
// their mean pressure and their centroid.
void TactileSensor::summarise(TactileImage& img) const {
  double sum = 0;
  glm::dvec2 centroid(0.0);
  for (int i = 0; i < sensor_.rows; ++i)
    for (int j = 0; j < sensor_.cols; ++j) {
      const double p = img.pressure[static_cast<std::size_t>(i * sensor_.cols + j)];
      if (p <= skin_.contact_threshold_kpa) continue;
      ++img.contacts;
      sum += p;
      centroid += p * glm::dvec2((j - 0.5 * (sensor_.cols - 1)) * sensor_.pitch_mm,
                                 (i - 0.5 * (sensor_.rows - 1)) * sensor_.pitch_mm);
    }
  if (img.contacts > 0) {
    img.mean_contact_kpa = sum / img.contacts;
    img.contact_centroid = centroid / sum;
  }
}

}  // namespace sva::sim
