#include "appearance/normal_confidence.hpp"

#include <sva/base/symmetric_eigen3.hpp>

#include <algorithm>
#include <cmath>

namespace sva::appearance {

std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& m) {
  std::array<double, 3> ev = symmetric_eigen3(m).values;
  std::sort(ev.begin(), ev.end(), [](double x, double y) { return x > y; });
  return ev;
}

float normal_confidence(const std::vector<float>& pressure, const SensorSpec& sensor, double stiffness_kpa_per_mm,
                        double threshold_kpa) {
  std::vector<std::array<double, 3>> pts;
  for (int r = 0; r < sensor.rows; ++r)
    for (int c = 0; c < sensor.cols; ++c) {
      const double p = pressure[static_cast<std::size_t>(r * sensor.cols + c)];
      if (!(p > threshold_kpa)) continue;  // also drops NaN
      pts.push_back({(c - 0.5 * (sensor.cols - 1)) * sensor.pitch_mm, (r - 0.5 * (sensor.rows - 1)) * sensor.pitch_mm,
                     p / stiffness_kpa_per_mm});
    }
  if (pts.size() < 3) return 0.0f;
  std::array<double, 3> mean{0, 0, 0};
  for (const auto& p : pts)
    for (int k = 0; k < 3; ++k) mean[k] += p[k];
  for (double& v : mean) v /= static_cast<double>(pts.size());
  std::array<std::array<double, 3>, 3> scatter{};
  for (const auto& p : pts)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) scatter[i][j] += (p[i] - mean[i]) * (p[j] - mean[j]);
  const auto ev = symmetric_eigenvalues(scatter);
  // Singular values of the centred point matrix are the square roots of the
  // scatter's eigenvalues; a second one below 1e-6 of the first is a line.
  if (!(ev[0] > 0) || !(ev[1] > 1e-12 * ev[0])) return 0.0f;
  const double ratio = std::sqrt(ev[1] / ev[0]);
  return static_cast<float>(std::clamp(ratio, 0.0, 1.0));
}

}  // namespace sva::appearance
