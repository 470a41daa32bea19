#pragma once
// Tactile appearance descriptors (paper Sec 1.1, after [15]): MN rotates the
// pressure image to the canonical orientation given by its moments; MNTI keeps
// the magnitudes of the low spatial frequencies of the MN image, which makes
// it robust to small translations. Parameters and interpolation are
// documented in docs/appearance.md.
#include <cstdint>
#include <vector>

namespace sva::appearance {

// The MN image: out_size x out_size bilinear samples at one element pitch on a
// grid centred on the image centroid and aligned with its principal axis
// (sign fixed by the third moment along it). Elements outside the sensor read
// as zero. `image` is rows x cols, row-major, non-negative with a positive sum.
std::vector<float> moment_normalise(const std::vector<float>& image, int rows, int cols, std::uint32_t out_size);

// Magnitudes |F(kx, ky)| of the 2D DFT of `mn` (size x size) zero-padded to
// pad x pad, for the half plane ky = 0, 0 <= kx < freqs and 0 < ky < freqs,
// |kx| < freqs (a real image's spectrum is conjugate-symmetric, so this keeps
// every distinct magnitude once).
std::vector<float> fourier_magnitudes(const std::vector<float>& mn, std::uint32_t size, std::uint32_t pad,
                                      std::uint32_t freqs);
std::uint32_t fourier_magnitude_count(std::uint32_t freqs);

// Scales v to unit length; returns false (leaving v unchanged) when its norm is
// zero or not finite.
bool normalise_unit(std::vector<float>& v);

// Inner product of two descriptors: the affinity of the paper.
float affinity(const float* a, const float* b, std::uint32_t n);

}  // namespace sva::appearance
