#include "appearance/normal_confidence.hpp"

#include <algorithm>
#include <cmath>

namespace sva::appearance {

std::array<double, 3> symmetric_eigenvalues(const std::array<std::array<double, 3>, 3>& m) {
  double a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = 0.5 * (m[i][j] + m[j][i]);
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * diag || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        // Rotation that zeroes a[p][q] (Golub & Van Loan 8.4, the stable form).
        const double tau = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (tau >= 0 ? 1.0 : -1.0) / (std::fabs(tau) + std::sqrt(1.0 + tau * tau));
        const double c = 1.0 / std::sqrt(1.0 + t * t), s = t * c;
        for (int k = 0; k < 3; ++k) {
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
      }
  }
  std::array<double, 3> ev{a[0][0], a[1][1], a[2][2]};
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
