// sva calibrate: records the array's zero counts (tare) from unloaded frames,
// read live from the device or from a session recording, and writes the
// calibration file. Gains come from the base calibration (fit them against
// known loads: docs/usb-sensor.md).
#include <sva/drivers/session.hpp>
#include <sva/drivers/usb_transport.hpp>

#include <cstdio>
#include <cstdlib>

#include "args.hpp"

namespace sva::cli {

namespace {

drivers::Calibration base_calibration(const Args& a) {
  if (auto file = a.get("--calibration")) return drivers::Calibration::load(*file);
  SensorSpec s;
  s.rows = static_cast<int>(a.integer("--rows", 6, 1, 255));
  s.cols = static_cast<int>(a.integer("--cols", 6, 1, 255));
  s.pitch_mm = a.number("--pitch", 2.0, 1e-6, 1e6);
  return drivers::Calibration::uniform(s, static_cast<float>(a.number("--gain", 1.0, 0.0, 1e9)), 0.0f);
}

std::unique_ptr<drivers::Transport> open_source(const Args& a) {
  if (auto session = a.get("--session"))
    return std::make_unique<drivers::ReplayTransport>(drivers::load_session(*session).chunks, 0.0, *session);
  drivers::UsbOptions usb;
  usb.device = drivers::DeviceSelector::parse(a.required("--device"));
  usb.interface_number = static_cast<int>(a.integer("--interface", 0, 0, 255));
  return std::make_unique<drivers::UsbTransport>(usb);
}

}  // namespace

int cmd_calibrate(const std::vector<std::string>& argv) {
  Args a("sva calibrate",
         "Record the array's zero counts from N unloaded frames (keep the sensor in the air) and write the\n"
         "calibration file: the gains of --calibration, or a uniform --gain for a --rows x --cols array.",
         argv);
  a.option("--device", "SERIAL|VID:PID|BUS-PORT", "read the sensor live")
      .option("--session", "SESSION", "or read the first frames of a recording")
      .option("--out", "CAL.json", "the calibration file to write")
      .option("--calibration", "BASE.json", "gains (and array size) to keep; only the zeros are replaced")
      .option("--frames", "N", "unloaded frames to average (default 100)")
      .option("--rows", "R", "array rows without --calibration (default 6)")
      .option("--cols", "C", "array columns without --calibration (default 6)")
      .option("--pitch", "MM", "element pitch without --calibration (default 2)")
      .option("--gain", "KPA", "kPa per count without --calibration (default 1)")
      .option("--interface", "N", "USB interface number (default 0)");
  if (!a.parse()) return 0;
  if (a.has("--device") == a.has("--session")) throw Error("sva calibrate: give exactly one of --device, --session");
  const std::string out = a.required("--out");
  auto calibration = base_calibration(a);
  const int count = static_cast<int>(a.integer("--frames", 100, 1, 1000000));
  drivers::StreamOptions options;
  options.rows = calibration.sensor.rows;
  options.cols = calibration.sensor.cols;
  options.block_when_full = true;
  drivers::SensorStream stream(open_source(a), options);
  calibration.tare(drivers::collect_frames(stream, count, std::chrono::milliseconds(5000)));
  calibration.save(out);
  double lo = calibration.zero[0], hi = calibration.zero[0];
  for (float z : calibration.zero) lo = std::min<double>(lo, z), hi = std::max<double>(hi, z);
  std::printf("wrote %s: zero counts from %d frames of %s, %.1f .. %.1f\n", out.c_str(), count,
              stream.describe().c_str(), lo, hi);
  return 0;
}

}  // namespace sva::cli
