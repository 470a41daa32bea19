#pragma once
// A real tactile array over USB (libusb-1.0). The sensor streams frames of raw
// element counts on a bulk IN endpoint; the driver validates each frame,
// applies the per-element calibration to kPa and returns a pressure image in
// the same layout as the simulator's, so recognition cannot tell them apart.
// Frame format and calibration file: docs/usb-sensor.md.
#include <sva/reading.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sva::drivers {

struct TactileFrame {
  std::uint16_t sequence = 0;
  int rows = 0, cols = 0;
  std::vector<std::uint16_t> counts;  // row-major raw ADC counts
};

// Parses one frame; throws sva::Error describing the fault (bad magic, size,
// CRC). Pure function: the part of the driver that is tested without hardware.
TactileFrame parse_frame(std::span<const std::uint8_t> bytes);
// The frame encoder (for tests and sensor emulators).
std::vector<std::uint8_t> encode_frame(const TactileFrame& frame);
std::uint16_t crc16_ccitt(std::span<const std::uint8_t> bytes);

// kPa = gain * (counts - zero), clamped at 0, per element.
struct Calibration {
  SensorSpec sensor;
  std::vector<float> gain;  // kPa per count
  std::vector<float> zero;  // counts at no load
  static Calibration uniform(const SensorSpec& sensor, float gain, float zero);
  static Calibration load(const std::filesystem::path& json_file);
  std::vector<float> to_pressure(const TactileFrame& frame) const;
};

struct UsbDeviceInfo {
  std::uint16_t vendor_id, product_id;
  int bus, address;
};

struct UsbSensorOptions {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  int interface_number = 0;
  std::uint8_t endpoint = 0x81;
  unsigned timeout_ms = 1000;
};

// Lists attached USB devices; throws sva::Error when USB is unavailable.
std::vector<UsbDeviceInfo> list_usb_devices();

class UsbTactileSensor {
 public:
  UsbTactileSensor(const UsbSensorOptions& options, Calibration calibration);
  ~UsbTactileSensor();
  UsbTactileSensor(const UsbTactileSensor&) = delete;
  UsbTactileSensor& operator=(const UsbTactileSensor&) = delete;
  // Blocks for the next frame (up to the timeout) and returns its pressure image.
  std::vector<float> read_pressure();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Calibration calibration_;
};

}  // namespace sva::drivers
