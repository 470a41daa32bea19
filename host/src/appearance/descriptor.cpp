#include "appearance/descriptor.hpp"

#include <sva/base/portable_math.hpp>

#include <cassert>
#include <cmath>
#include <numbers>

namespace sva::appearance {

namespace {

// Bilinear interpolation over element centres; off-sensor elements are zero,
// so content near the sensor edge fades out instead of being clamped.
double sample(const std::vector<float>& image, int rows, int cols, double u, double v) {
  const double fu = std::floor(u), fv = std::floor(v);
  const int c0 = static_cast<int>(fu), r0 = static_cast<int>(fv);
  const double tu = u - fu, tv = v - fv;
  auto at = [&](int r, int c) -> double {
    if (r < 0 || c < 0 || r >= rows || c >= cols) return 0.0;
    return image[static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)];
  };
  return (1 - tv) * ((1 - tu) * at(r0, c0) + tu * at(r0, c0 + 1)) +
         tv * ((1 - tu) * at(r0 + 1, c0) + tu * at(r0 + 1, c0 + 1));
}

}  // namespace

std::vector<float> moment_normalise(const std::vector<float>& image, int rows, int cols, std::uint32_t out_size) {
  assert(image.size() == static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols));
  double m = 0, mx = 0, my = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double w = image[static_cast<std::size_t>(r * cols + c)];
      m += w;
      mx += w * c;
      my += w * r;
    }
  assert(m > 0);
  const double cx = mx / m, cy = my / m;
  double mu20 = 0, mu02 = 0, mu11 = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double w = image[static_cast<std::size_t>(r * cols + c)];
      const double dx = c - cx, dy = r - cy;
      mu20 += w * dx * dx;
      mu02 += w * dy * dy;
      mu11 += w * dx * dy;
    }
  const double theta = 0.5 * pmath::atan2(2.0 * mu11, mu20 - mu02);
  double ex = pmath::cos(theta), ey = pmath::sin(theta);
  // The principal axis has no direction; the skew of the mass along it
  // (third moment) picks one, resolving the 180 degree ambiguity.
  double m3 = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double w = image[static_cast<std::size_t>(r * cols + c)];
      const double s = (c - cx) * ex + (r - cy) * ey;
      m3 += w * s * s * s;
    }
  if (m3 < 0) {
    ex = -ex;
    ey = -ey;
  }
  std::vector<float> out(static_cast<std::size_t>(out_size) * out_size);
  const double half = (static_cast<double>(out_size) - 1.0) / 2.0;
  for (std::uint32_t i = 0; i < out_size; ++i)
    for (std::uint32_t j = 0; j < out_size; ++j) {
      const double qx = j - half, qy = i - half;
      // Canonical frame: x along the principal axis, y its left-hand normal.
      const double u = cx + qx * ex - qy * ey;
      const double v = cy + qx * ey + qy * ex;
      out[static_cast<std::size_t>(i) * out_size + j] = static_cast<float>(sample(image, rows, cols, u, v));
    }
  return out;
}

std::uint32_t fourier_magnitude_count(std::uint32_t freqs) {
  return freqs == 0 ? 0 : freqs + (freqs - 1) * (2 * freqs - 1);
}

std::vector<float> fourier_magnitudes(const std::vector<float>& mn, std::uint32_t size, std::uint32_t pad,
                                      std::uint32_t freqs) {
  assert(mn.size() == static_cast<std::size_t>(size) * size && pad >= size && freqs <= pad / 2 + 1);
  std::vector<float> out;
  out.reserve(fourier_magnitude_count(freqs));
  const double step = 2.0 * std::numbers::pi / pad;
  // A direct DFT of the few coefficients we keep: 25 x 64 terms, cheaper than an FFT of the padded grid.
  auto coefficient = [&](int kx, int ky) {
    double re = 0, im = 0;
    for (std::uint32_t y = 0; y < size; ++y)
      for (std::uint32_t x = 0; x < size; ++x) {
        const double f = mn[static_cast<std::size_t>(y) * size + x];
        if (f == 0) continue;
        const double a = -step * (kx * static_cast<double>(x) + ky * static_cast<double>(y));
        re += f * pmath::cos(a);
        im += f * pmath::sin(a);
      }
    return static_cast<float>(pmath::hypot(re, im));
  };
  const int k = static_cast<int>(freqs);
  for (int kx = 0; kx < k; ++kx) out.push_back(coefficient(kx, 0));
  for (int ky = 1; ky < k; ++ky)
    for (int kx = -(k - 1); kx < k; ++kx) out.push_back(coefficient(kx, ky));
  return out;
}

bool normalise_unit(std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += static_cast<double>(x) * x;
  if (!(s > 0) || !std::isfinite(s)) return false;
  const double inv = 1.0 / std::sqrt(s);
  for (float& x : v) x = static_cast<float>(x * inv);
  return true;
}

float affinity(const float* a, const float* b, std::uint32_t n) {
  float s = 0;
  for (std::uint32_t i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

}  // namespace sva::appearance
