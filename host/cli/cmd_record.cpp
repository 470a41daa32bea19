// sva record: records a real tactile array (USB) and the arm's pose stream into
// a session file, forming readings as contacts settle (printed as JSON lines)
// and, with a map, recognising while touching (the estimate after each).
// Ctrl-C ends the recording; the file is valid up to its last record whatever
// happens.
#include <sva/base/interrupt.hpp>
#include <sva/drivers/session.hpp>
#include <sva/drivers/usb_transport.hpp>
#include <sva/recognizer.hpp>

#include <cstdio>
#include <cstdlib>

#include "args.hpp"
#include "sensor_output.hpp"

namespace sva::cli {

namespace {

std::uint8_t parse_endpoint(const std::string& text) {
  char* end = nullptr;
  const unsigned long v = std::strtoul(text.c_str(), &end, 0);
  if (text.empty() || *end != '\0' || v > 0xff) throw Error("--endpoint " + text + ": expected an address like 0x81");
  return static_cast<std::uint8_t>(v);
}

drivers::SettleRule settle_rule(const Args& a) {
  drivers::SettleRule r;
  r.frames = static_cast<int>(a.integer("--settle-frames", r.frames, 1, 10000));
  r.target_kpa = a.number("--target-kpa", r.target_kpa, 0, 1e6);
  r.tolerance_kpa = a.number("--tolerance-kpa", r.tolerance_kpa, 0, 1e6);
  r.stable_kpa = a.number("--stable-kpa", r.stable_kpa, 0, 1e6);
  r.contact_kpa = a.number("--contact-kpa", r.contact_kpa, 1e-9, 1e6);
  r.pose_clock_offset_s = a.number("--pose-clock-offset", r.pose_clock_offset_s, -1e9, 1e9);
  r.validate();
  return r;
}

void declare_options(Args& a, bool live) {
  a.option("--device", "SERIAL|VID:PID|BUS-PORT", "which sensor")
      .option("--calibration", "CAL.json", "the array's calibration (docs/usb-sensor.md)")
      .option("--poses", "POSES.jsonl|-", "the arm's pose stream: a file, a named pipe, or - for stdin")
      .option("--out", "SESSION", live ? "also record the session into this file" : "the recording to write")
      .flag("--append", "continue an existing recording (its calibration and settle rule are kept)")
      .option("--interface", "N", "USB interface number (default 0)")
      .option("--endpoint", "ADDR", "bulk IN endpoint, e.g. 0x81 (default)")
      .flag("--no-hotplug", "after a disconnect, poll every 0.5 s instead of waiting for libusb's hotplug events")
      .option("--duration", "S", "stop after this many seconds (default: until Ctrl-C)")
      .option("--settle-frames", "N", "consecutive stable frames that settle a contact (default 5)")
      .option("--target-kpa", "KPA", "the contact controller's target mean pressure (default 0: any)")
      .option("--tolerance-kpa", "KPA", "allowed distance of the mean pressure from the target (default 5)")
      .option("--stable-kpa", "KPA", "largest change of any element between settled frames (default 1)")
      .option("--contact-kpa", "KPA", "mean pressure that starts (and, below it, ends) a contact (default 0.5)")
      .option("--pose-clock-offset", "S",
              "seconds added to the pose stream's times before matching (arm clock + S = host monotonic clock; "
              "default 0); saved with the recording")
      .option("--map", "MAP",
              live ? "the map to recognise with: the estimate after each converged reading on stdout"
                   : "recognise while touching: the estimate after each converged reading on stdout")
      .option("--backend", "cpu|vulkan|auto", "vote backend with --map (default auto)");
}

// sva record and sva live: one loop; record must write a file, live must recognise.
int run_sensor(const std::string& name, Args& a, bool live) {
  drivers::UsbOptions usb;
  usb.device = drivers::DeviceSelector::parse(a.required("--device"));
  usb.interface_number = static_cast<int>(a.integer("--interface", 0, 0, 255));
  usb.endpoint = parse_endpoint(a.get_or("--endpoint", "0x81"));
  usb.hotplug = !a.has("--no-hotplug");
  drivers::SessionSettings settings{drivers::Calibration::load(a.required("--calibration")), settle_rule(a),
                                    "USB " + usb.device.describe()};
  const double duration = a.number("--duration", 0, 0, 1e7);
  const std::string poses_source = a.required("--poses");
  const std::string out = live ? a.get_or("--out", "") : a.required("--out");
  const std::string map = live ? a.required("--map") : a.get_or("--map", "");

  auto transport = std::make_unique<drivers::UsbTransport>(usb);
  std::fprintf(stderr, "%s: %s opened; if the cable is pulled, it is found again by %s\n", name.c_str(),
               transport->describe().c_str(), transport->reconnect_plan().message.c_str());
  std::unique_ptr<drivers::SessionWriter> writer;
  if (!out.empty()) {
    writer = std::make_unique<drivers::SessionWriter>(out, settings, a.has("--append"));
    if (a.has("--append")) {
      const double offset = settings.settle.pose_clock_offset_s;
      settings = drivers::load_session(out).settings;
      // One offset per recording, so that a replay matches every pose as the live run did.
      if (a.has("--pose-clock-offset") && offset != settings.settle.pose_clock_offset_s)
        throw Error(name + ": --pose-clock-offset " + a.required("--pose-clock-offset") + " differs from " + out +
                    "'s own (" + std::to_string(settings.settle.pose_clock_offset_s) +
                    " s); a recording keeps one offset: start a new one");
    }
  }
  drivers::PoseStream poses(poses_source);
  drivers::LiveOptions opts{settings, writer.get()};
  const auto start = drivers::monotonic_ns();
  opts.keep_going = [&] {
    return !util::interrupted() && (duration == 0 || drivers::monotonic_ns() - start < duration * 1e9);
  };
  ReadingPrinter printer(name, map, parse_backend_kind(a.get_or("--backend", "auto"), name + ": --backend"));
  drivers::PipelineEvents events;
  events.on_reading = [&](const drivers::FormedReading& r, std::int64_t) { printer(r); };
  events.on_note = [&](const drivers::ContactNote& n) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), n.text.c_str());
  };
  events.on_link = [&](const drivers::SensorEvent& e) {
    std::fprintf(stderr, "%s: link %s: %s\n", name.c_str(), drivers::to_string(e.status), e.message.c_str());
  };
  const auto s = drivers::run_live(std::move(transport), poses, opts, events);
  std::fprintf(stderr,
               "%s: %s%s%zu readings, %llu frames, %llu CRC errors, %llu frames missing, %llu dropped by a slow "
               "consumer, %llu disconnects\n",
               name.c_str(), out.empty() ? "" : "wrote ", out.empty() ? "" : (out + ": ").c_str(), printer.readings(),
               static_cast<unsigned long long>(s.parser.frames), static_cast<unsigned long long>(s.parser.crc_errors),
               static_cast<unsigned long long>(s.parser.frames_missing),
               static_cast<unsigned long long>(s.ring_overflows), static_cast<unsigned long long>(s.disconnects));
  util::clear_interrupt();  // Ctrl-C is how a session ends: the file is complete
  return 0;
}

}  // namespace

int cmd_record(const std::vector<std::string>& argv) {
  Args a("sva record",
         "Record a tactile array over USB and the arm's pose stream (JSON lines: time, position, normal, x_axis,\n"
         "optional status; time in seconds on this machine's monotonic clock) into SESSION. Readings are formed\n"
         "as contacts settle and printed as JSON lines. Ctrl-C (or --duration) stops; the recording is valid up to its "
         "last record even after a crash. See docs/usb-sensor.md.",
         argv);
  declare_options(a, false);
  if (!a.parse()) return 0;
  return run_sensor("sva record", a, false);
}

int cmd_live(const std::vector<std::string>& argv) {
  Args a("sva live",
         "Recognise while touching: a tactile array over USB and the arm's pose stream (as sva record) feed the\n"
         "recognizer; after each settled reading the estimate (object probabilities, best pose, hypotheses) goes to\n"
         "stdout as a JSON line and a one-line summary to stderr. --out also records the session. Ctrl-C stops.\n"
         "See docs/usb-sensor.md.",
         argv);
  declare_options(a, true);
  if (!a.parse()) return 0;
  return run_sensor("sva live", a, true);
}

}  // namespace sva::cli
