// Calibration JSON (drivers/src/calibration.cpp, docs/usb-sensor.md).
#include <sva/drivers/calibration.hpp>
#include <sva/error.hpp>

#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto c =
        sva::drivers::Calibration::from_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz/cal.json");
    // A calibration that loads must convert a frame of its size.
    sva::drivers::TactileFrame f;
    f.rows = c.sensor.rows;
    f.cols = c.sensor.cols;
    f.counts.assign(static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols), 1000);
    if (c.to_pressure(f).size() != f.counts.size()) std::abort();
    (void)sva::drivers::Calibration::from_json(c.to_json(), "fuzz/cal.json (written again)");
  } catch (const sva::Error&) {
  }
  return 0;
}
