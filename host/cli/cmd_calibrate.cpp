// sva calibrate: records the array's zero counts (tare) from unloaded frames, read live from the device or from a
// session recording, and, given known loads (--load KPA, repeated), fits each element's gain against them; writes
// the calibration file. The fit is the library's (drivers::fit_gains); this command collects the frames and prints.
#include <sva/drivers/session.hpp>
#include <sva/drivers/usb_transport.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

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

std::vector<double> parse_loads(const Args& a) {
  std::vector<double> loads;
  for (const auto& text : a.all("--load")) {
    char* end = nullptr;
    const double kpa = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(kpa) || kpa <= 0)
      throw Error("sva calibrate: --load " + text + ": expected a pressure in kPa above 0");
    loads.push_back(kpa);
  }
  return loads;
}

// Live: the user presses the load and confirms on stdin; frames that arrived while waiting are stale.
void wait_for_press(drivers::SensorStream& stream, double kpa) {
  std::fprintf(stderr, "sva calibrate: press a flat %g kPa over the whole array and hold it, then press Enter\n", kpa);
  std::string line;
  if (!std::getline(std::cin, line))
    throw Error("sva calibrate: stdin ended before the " + std::to_string(kpa) + " kPa load was confirmed");
  while (stream.next(std::chrono::nanoseconds(0))) {
  }
}

// The loaded frames: per load, `skip` frames let the press settle, then `count` are kept. From a recording the
// presses follow the unloaded frames in the order of --load.
std::vector<drivers::LoadFrames> collect_loads(drivers::SensorStream& stream, const std::vector<double>& loads,
                                               bool live, int count, int skip) {
  std::vector<drivers::LoadFrames> out;
  for (double kpa : loads) {
    if (live) wait_for_press(stream, kpa);
    if (skip > 0) drivers::collect_frames(stream, skip, std::chrono::milliseconds(5000));
    out.push_back({kpa, drivers::collect_frames(stream, count, std::chrono::milliseconds(5000))});
  }
  return out;
}

void print_fit(const drivers::GainFit& fit, const drivers::Calibration& c) {
  std::printf(
      "gain fit: %d loads, %zu frames: gain %.6g .. %.6g kPa/count; residual %.4g kPa RMS (%.2f%% of the loads), "
      "worst element %d (row %d, col %d) %.4g kPa RMS\n",
      fit.loads, fit.frames, fit.min_gain, fit.max_gain, fit.rms_residual_kpa, 100 * fit.relative_residual,
      fit.worst_element, fit.worst_element / c.sensor.cols, fit.worst_element % c.sensor.cols, fit.worst_residual_kpa);
}

}  // namespace

int cmd_calibrate(const std::vector<std::string>& argv) {
  Args a("sva calibrate",
         "Record the array's zero counts from N unloaded frames (keep the sensor in the air) and write the\n"
         "calibration file: the gains of --calibration, or a uniform --gain for a --rows x --cols array. With\n"
         "--load KPA (repeated), also fit each element's gain against those known flat loads: after the zero\n"
         "frames, each load is pressed in turn (live: confirm each press with Enter) and N frames are recorded\n"
         "(docs/usb-sensor.md, \"Calibrate\").",
         argv);
  a.option("--device", "SERIAL|VID:PID|BUS-PORT", "read the sensor live")
      .option("--session", "SESSION", "or read the frames of a recording (zero frames first, then each load's)")
      .option("--out", "CAL.json", "the calibration file to write")
      .option("--calibration", "BASE.json", "gains (and array size) to keep; only the zeros are replaced")
      .option("--frames", "N", "frames to average at no load and per load (default 100)")
      .option("--load", "KPA", "a known flat pressure to fit the gains against (repeat for several)", true)
      .option("--skip", "N", "frames discarded after each press while it settles (default 20)")
      .option("--max-residual", "F", "refuse a fit whose RMS residual exceeds this fraction of the loads (0.25)")
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
  const int skip = static_cast<int>(a.integer("--skip", 20, 0, 1000000));
  const std::vector<double> loads = parse_loads(a);
  drivers::GainFitOptions fit_options;
  fit_options.max_relative_residual = a.number("--max-residual", fit_options.max_relative_residual, 0.0, 1e6);
  drivers::StreamOptions options;
  options.rows = calibration.sensor.rows;
  options.cols = calibration.sensor.cols;
  options.block_when_full = true;
  drivers::SensorStream stream(open_source(a), options);
  const auto unloaded = drivers::collect_frames(stream, count, std::chrono::milliseconds(5000));
  if (loads.empty()) {
    calibration.tare(unloaded);
  } else {
    const auto loaded = collect_loads(stream, loads, a.has("--device"), count, skip);
    print_fit(drivers::fit_gains(calibration, unloaded, loaded, fit_options), calibration);
  }
  calibration.save(out);
  double lo = calibration.zero[0], hi = calibration.zero[0];
  for (float z : calibration.zero) lo = std::min<double>(lo, z), hi = std::max<double>(hi, z);
  std::printf("wrote %s: zero counts from %d frames of %s, %.1f .. %.1f%s\n", out.c_str(), count,
              stream.describe().c_str(), lo, hi, loads.empty() ? "" : "; gains fitted");
  return 0;
}

}  // namespace sva::cli
