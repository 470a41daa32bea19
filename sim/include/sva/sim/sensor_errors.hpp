#pragma once
// The scene's error model (sva::ErrorModel, docs/sensor-model.md "Error
// model") applied to what the robot reports: one physical array's fixed
// element gains and offsets, its crosstalk, per-frame noise and saturation;
// and the arm's error on the reported sensor pose.
#include <sva/reading.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <vector>

namespace sva::sim {

// One physical tactile array. Its element gains and offsets are drawn once
// from the sensor instance seed, so two seeds are two sensors and one seed is
// the same sensor in every run.
class SensorInstance {
 public:
  SensorInstance(const SensorSpec& sensor, const ErrorModel& errors, std::uint64_t instance_seed,
                 double skin_noise_kpa = 0.0);
  // What the array reports for the physical (noise-free) pressure field, kPa,
  // row-major: crosstalk, then gain and offset, then frame noise (from
  // `frame_seed`), then clipping to [0, full scale].
  std::vector<float> read(const std::vector<double>& physical_kpa, std::uint64_t frame_seed) const;
  const std::vector<double>& gains() const { return gains_; }
  const std::vector<double>& offsets() const { return offsets_; }

 private:
  std::vector<double> crosstalk(const std::vector<double>& p) const;

  SensorSpec sensor_;
  ErrorModel errors_;
  double noise_kpa_;
  std::vector<double> gains_, offsets_;
};

// The frame the arm reports for a sensor truly at (position, normal, x_axis):
// the position moved by N(0, position_sigma^2) per axis, the frame turned by a
// rotation vector of N(0, normal_sigma^2) per axis (world frame). Exactly the
// truth when both sigmas are 0.
void report_pose(const ErrorModel& errors, std::uint64_t seed, glm::dvec3& position, glm::dvec3& normal,
                 glm::dvec3& x_axis);

}  // namespace sva::sim
