// AppearanceModel: describe (MN/MNTI), normConf (Algorithm 1), classify
// (Eq 8-12); DistanceBins (Eq 13).
#include "appearance/appearance_model.hpp"

#include <sva/error.hpp>

#include <cmath>

#include "appearance/descriptor.hpp"
#include "appearance/normal_confidence.hpp"
#include "appearance/soft_classes.hpp"

namespace sva {

std::vector<BinWeight> DistanceBins::bins(double d) const {
  if (!(d >= min_mm && d <= max_mm) || count == 0) return {};
  const double width = (max_mm - min_mm) / count;
  // Position in bin-centre units: centre i sits at t = i (Eq 13).
  const double t = (d - min_mm) / width - 0.5;
  if (t <= 0) return {{0, 1.0f}};
  if (t >= count - 1) return {{count - 1, 1.0f}};
  const double lo = std::floor(t);
  const double f = t - lo;
  const auto i = static_cast<std::uint32_t>(lo);
  if (f == 0) return {{i, 1.0f}};
  const float w_hi = static_cast<float>(f);
  const float w_lo = 1.0f - w_hi;
  if (w_lo <= 0) return {{i + 1, 1.0f}};
  if (w_hi <= 0) return {{i, 1.0f}};
  return {{i, w_lo}, {i + 1, w_hi}};
}

std::string AppearanceModel::why_not_describable(const Reading& r) const {
  const auto& s = calibration.sensor;
  if (r.pressure.size() != static_cast<std::size_t>(s.elements()))
    return "pressure image has " + std::to_string(r.pressure.size()) + " elements, the sensor has " +
           std::to_string(s.elements());
  bool contact = false;
  double mass = 0;
  for (float p : r.pressure) {
    if (!std::isfinite(p)) return "pressure image has a non-finite value";
    contact = contact || p > calibration.contact_threshold_kpa;
    mass += p > 0 ? p : 0.0f;
  }
  // The mass test matters only for a threshold <= 0: moments need weight.
  if (!contact || !(mass > 0))
    return "no element is above the contact threshold (" + std::to_string(calibration.contact_threshold_kpa) + " kPa)";
  return {};
}

std::vector<float> AppearanceModel::describe(const Reading& r) const {
  if (auto why = why_not_describable(r); !why.empty()) throw Error("reading cannot be described: " + why);
  std::vector<float> image(r.pressure.size());
  for (std::size_t i = 0; i < image.size(); ++i) image[i] = r.pressure[i] > 0 ? r.pressure[i] : 0.0f;
  std::vector<float> d = appearance::moment_normalise(image, calibration.sensor.rows, calibration.sensor.cols, mn_size);
  if (descriptor == DescriptorKind::mnti) d = appearance::fourier_magnitudes(d, mn_size, mnti_pad, mnti_freqs);
  // The contact mass can sit entirely off the resampling grid only for absurd
  // parameters; treat it as indescribable rather than return a zero vector.
  if (!appearance::normalise_unit(d)) throw Error("reading cannot be described: its descriptor is zero");
  return d;
}

std::vector<ClassWeight> AppearanceModel::classify(const std::vector<float>& d) const {
  if (n_classes() == 0) throw Error("appearance model has no classes");
  if (d.size() != descriptor_size)
    throw Error("descriptor has " + std::to_string(d.size()) + " values, the model expects " +
                std::to_string(descriptor_size));
  for (float v : d)
    if (!std::isfinite(v)) throw Error("descriptor has a non-finite value");
  return appearance::soft_classes(d.data(), medoids, psi, descriptor_size, prune_ratio);
}

float AppearanceModel::norm_conf(const Reading& r) const {
  if (r.pressure.size() != static_cast<std::size_t>(calibration.sensor.elements()))
    throw Error("reading has " + std::to_string(r.pressure.size()) + " pressure values, the sensor has " +
                std::to_string(calibration.sensor.elements()));
  return appearance::normal_confidence(r.pressure, calibration.sensor, calibration.stiffness_kpa_per_mm,
                                       calibration.contact_threshold_kpa);
}

}  // namespace sva
