#pragma once
// Appearance: descriptors (MN, MNTI), normal confidence (Algorithm 1), soft
// appearance classes (Eq 7-12) and distance bins (Eq 13). Owned by the
// appearance issue; the recognizer uses only what is declared here.
#include <sva/reading.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sva {

enum class DescriptorKind : std::uint8_t { mn = 0, mnti = 1 };

struct ClassWeight {
  std::uint32_t cls;
  float weight;  // Pr(z | c) after pruning and renormalisation (Eq 12); weights of a reading sum to 1
};

struct BinWeight {
  std::uint32_t bin;
  float weight;  // linear interpolation weight (Eq 13); weights sum to 1
};

struct DistanceBins {
  std::uint32_t count = 40;
  double min_mm = 30.0;
  double max_mm = 160.0;
  // Up to two bins with weights summing to 1; empty when outside [min, max].
  std::vector<BinWeight> bins(double distance_mm) const;
};

// The calibration the descriptors and normConf need from the sensor model.
struct SensorCalibration {
  SensorSpec sensor;
  double stiffness_kpa_per_mm = 100.0;  // inverse of the simulator's pressure calibration (depth from pressure)
  double contact_threshold_kpa = 2.0;
};

class AppearanceModel {
 public:
  DescriptorKind descriptor = DescriptorKind::mnti;
  SensorCalibration calibration;
  // Descriptor parameters (docs/appearance.md): the MN image is mn_size x
  // mn_size samples at one element pitch around the centroid; MNTI pads it to
  // mnti_pad x mnti_pad and keeps |F(kx, ky)| for |kx|, ky < mnti_freqs
  // (half plane, so no coefficient is counted twice).
  std::uint32_t mn_size = 8;
  std::uint32_t mnti_pad = 16;
  std::uint32_t mnti_freqs = 4;
  std::uint32_t descriptor_size = 0;
  std::vector<float> medoids;  // n_classes x descriptor_size, unit rows
  std::vector<float> psi;      // Eq 7 per class (a variance)
  float prune_ratio = 0.75f;   // T_a

  std::uint32_t n_classes() const { return static_cast<std::uint32_t>(psi.size()); }
  // Unit-length descriptor of a reading's pressure image. Throws sva::Error
  // when the image cannot be described (wrong size, non-finite values, no
  // element above the contact threshold); see describable().
  std::vector<float> describe(const Reading& r) const;
  // Why a reading cannot be described, or "" when it can.
  std::string why_not_describable(const Reading& r) const;
  // Soft classes of a descriptor (Eq 8-12): non-empty, weights sum to 1.
  std::vector<ClassWeight> classify(const std::vector<float>& descriptor) const;
  // Algorithm 1 on a reading's image.
  float norm_conf(const Reading& r) const;
};

}  // namespace sva
