// The error model of docs/sensor-model.md: what stands between the physical
// contact and what the robot reports. The order follows the signal: the
// electrodes couple (crosstalk), each element has its own sensitivity and zero
// (gain, offset), the electronics add noise, the converter clips at full scale.
#include <sva/error.hpp>
#include <sva/sim/sensor_errors.hpp>

#include <algorithm>
#include <cmath>

#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

namespace sva::sim {

namespace {

constexpr std::uint64_t kInstanceStream = 0x696e7374616e6365ull;  // "instance"
constexpr std::uint64_t kNoiseStream = 0x6e6f697365ull;           // "noise" (the skin noise's stream of old)
constexpr std::uint64_t kArmStream = 0x61726dull;                 // "arm"

// A standard normal clipped at 3 sigma: a gain never turns negative, however
// many elements a scene draws.
double clipped_normal(util::Rng& rng) { return std::clamp(rng.normal(), -3.0, 3.0); }

glm::dvec3 rotate(const glm::dvec3& v, const glm::dvec3& rotation_vector) {
  const double a = glm::length(rotation_vector);
  if (a == 0.0) return v;
  const glm::dvec3 k = rotation_vector / a;
  return so3::rotate(v, a, k);
}

}  // namespace

SensorInstance::SensorInstance(const SensorSpec& sensor, const ErrorModel& errors, std::uint64_t instance_seed,
                               double skin_noise_kpa)
    : sensor_(sensor), errors_(errors), noise_kpa_(pmath::hypot(skin_noise_kpa, errors.noise_kpa)) {
  if (sensor.elements() < 1) throw Error("sensor: the array has no elements");
  const auto n = static_cast<std::size_t>(sensor.elements());
  gains_.assign(n, 1.0);
  offsets_.assign(n, 0.0);
  util::Rng rng(instance_seed, kInstanceStream);
  for (std::size_t i = 0; i < n; ++i) {
    // Both draws always happen, so a sensor's gains do not change when only
    // its offset spread does.
    const double g = clipped_normal(rng), o = rng.normal();
    gains_[i] = 1.0 + errors.gain_spread * g;
    offsets_[i] = errors.offset_kpa * o;
  }
}

std::vector<double> SensorInstance::crosstalk(const std::vector<double>& p) const {
  const double c = errors_.crosstalk, cd = errors_.crosstalk_diagonal;
  if (c == 0.0 && cd == 0.0) return p;
  const int rows = sensor_.rows, cols = sensor_.cols;
  std::vector<double> out(p);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      double extra = 0;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          const int a = i + di, b = j + dj;
          if ((di == 0 && dj == 0) || a < 0 || a >= rows || b < 0 || b >= cols) continue;
          extra += (di == 0 || dj == 0 ? c : cd) * p[static_cast<std::size_t>(a * cols + b)];
        }
      out[static_cast<std::size_t>(i * cols + j)] += extra;
    }
  return out;
}

std::vector<float> SensorInstance::read(const std::vector<double>& physical_kpa, std::uint64_t frame_seed) const {
  if (physical_kpa.size() != gains_.size()) throw Error("sensor: pressure field has the wrong number of elements");
  const std::vector<double> coupled = crosstalk(physical_kpa);
  util::Rng noise(frame_seed, kNoiseStream);
  const double full_scale = errors_.full_scale_kpa > 0 ? errors_.full_scale_kpa : HUGE_VAL;
  std::vector<float> out(coupled.size());
  for (std::size_t i = 0; i < coupled.size(); ++i) {
    double p = gains_[i] * coupled[i] + offsets_[i];
    if (noise_kpa_ > 0) p += noise_kpa_ * noise.normal();
    out[i] = static_cast<float>(std::clamp(p, 0.0, full_scale));
  }
  return out;
}

void report_pose(const ErrorModel& errors, std::uint64_t seed, glm::dvec3& position, glm::dvec3& normal,
                 glm::dvec3& x_axis) {
  if (errors.arm_ideal()) return;
  util::Rng rng(seed, kArmStream);
  const double ps = errors.position_sigma_mm, rs = errors.normal_sigma_deg * M_PI / 180.0;
  // Component by component, z first: the order x86-64's GCC evaluated the constructors' arguments in (C++ leaves it
  // unspecified, and aarch64's GCC reversed it: issue 54).
  glm::dvec3 dp, w;
  dp.z = rng.normal(), dp.y = rng.normal(), dp.x = rng.normal();
  w.z = rng.normal(), w.y = rng.normal(), w.x = rng.normal();
  position += ps * dp;
  normal = glm::normalize(rotate(normal, rs * w));
  x_axis = rotate(x_axis, rs * w);
  x_axis = glm::normalize(x_axis - glm::dot(x_axis, normal) * normal);
}

}  // namespace sva::sim
