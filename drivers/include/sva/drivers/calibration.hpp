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

}  // namespace sva::drivers
