#pragma once
// Per-element calibration of a tactile array: raw counts to kPa in the
// simulator's layout, so recognition cannot tell hardware from simulation.
// File format: docs/usb-sensor.md.
#include <sva/drivers/frame.hpp>
#include <sva/reading.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace sva::drivers {

// kPa = gain * (counts - zero), clamped at 0, per element. An element at or
// above `saturation_counts` is saturated: its true pressure is unknown.
struct Calibration {
  SensorSpec sensor;
  std::vector<float> gain;  // kPa per count
  std::vector<float> zero;  // counts at no load
  std::uint16_t saturation_counts = 65535;

  static Calibration uniform(const SensorSpec& sensor, float gain, float zero);
  static Calibration load(const std::filesystem::path& json_file);
  static Calibration from_json(const std::string& text, const std::string& source);
  std::string to_json() const;
  void save(const std::filesystem::path& json_file) const;

  std::vector<float> to_pressure(const TactileFrame& frame) const;
  // Elements at or above saturation (0: none).
  int saturated(const TactileFrame& frame) const;
  // Re-zero: each element's zero becomes its mean count over these unloaded
  // frames. Throws when there are none or their size differs.
  void tare(std::span<const TactileFrame> unloaded);
  // The counts a pressure image reads as (nearest count; the inverse of
  // to_pressure up to one count): sensor emulators and `sva export`.
  std::vector<std::uint16_t> to_counts(std::span<const float> pressure) const;
};

// Frames recorded while a known, flat pressure was pressed over the whole array (a flat indenter of known area
// and weight): the data of a gain fit.
struct LoadFrames {
  double kpa = 0;
  std::vector<TactileFrame> frames;
};

struct GainFitOptions {
  // An element must rise at least this many counts above its zero under the heaviest load, and at least
  // `min_response_sigmas` times its own noise (the standard deviation of its unloaded counts): below that its
  // gain is mostly noise and the fit is refused as ill-conditioned.
  double min_response_counts = 2.0;
  double min_response_sigmas = 5.0;
  // The fit is refused when its RMS residual exceeds this fraction of the RMS load: the element does not
  // respond linearly (hysteresis, a load not flat over the array, a load list that does not match the presses).
  double max_relative_residual = 0.25;
};

// How well counts -> kPa fitted the loads.
struct GainFit {
  int loads = 0;                  // distinct loads fitted (> 0 kPa)
  std::size_t frames = 0;         // loaded frames fitted
  double rms_residual_kpa = 0;    // over every element and loaded frame
  double relative_residual = 0;   // rms_residual_kpa / RMS load
  double worst_residual_kpa = 0;  // the largest element's RMS residual
  int worst_element = 0;          // row-major index of that element
  double min_gain = 0, max_gain = 0;
};

// Fits the calibration against known loads: each element's zero is its mean count over `unloaded` (as tare),
// and its gain the least-squares slope through that zero, kPa = gain * (counts - zero), over every loaded frame.
// Refused with sva::Error naming the load or element: no unloaded frames, no load above 0 kPa, a load without
// frames or not finite, frames of another size, a saturated element under load, an element that barely responds
// or falls under load (ill-conditioned), or a residual above GainFitOptions::max_relative_residual. On error the
// calibration is unchanged.
GainFit fit_gains(Calibration& calibration, std::span<const TactileFrame> unloaded, std::span<const LoadFrames> loads,
                  const GainFitOptions& options = {});

}  // namespace sva::drivers
