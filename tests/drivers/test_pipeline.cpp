// A sensor emulator through the replay transport: the reader thread, link
// status changes, the settle rule and pose matching; and the USB transport's
// error paths that need no device.
#include <catch2/catch.hpp>

#include <sva/drivers/contact_readings.hpp>
#include <sva/drivers/sensor_stream.hpp>
#include <sva/drivers/usb_transport.hpp>
#include <sva/error.hpp>

using namespace sva::drivers;
using Catch::Contains;

namespace {

constexpr std::int64_t kMs = 1'000'000;

// Emulates a 6 x 6 array at 1 kHz: `pressure(k)` kPa on every element for frame k.
struct Emulator {
  Calibration calibration = Calibration::uniform({}, 0.01f, 1000.0f);
  std::uint16_t sequence = 0;
  std::int64_t ns = 1000 * kMs;
  std::vector<Chunk> chunks;

  std::vector<std::uint8_t> frame(float kpa) {
    std::vector<float> p(36, kpa);
    p[7] = kpa * 1.5f;
    return encode_frame(TactileFrame{sequence++, 6, 6, calibration.to_counts(p)});
  }
  void frames(int n, float kpa) {
    for (int i = 0; i < n; ++i, ns += kMs) chunks.push_back({LinkStatus::data, ns, frame(kpa), {}});
  }
  void status(LinkStatus s) { chunks.push_back({s, ns, {}, to_string(s)}); }
};

std::vector<SensorEvent> run_stream(std::vector<Chunk> chunks, double speed = 0, StreamStats* stats = nullptr) {
  StreamOptions o;
  o.rows = o.cols = 6;
  o.block_when_full = true;
  SensorStream stream(std::make_unique<ReplayTransport>(std::move(chunks), speed), o);
  std::vector<SensorEvent> events;
  while (auto e = stream.next(std::chrono::seconds(5))) events.push_back(std::move(*e));
  CHECK(stream.finished());
  if (stats) *stats = stream.stats();
  return events;
}

PoseSample pose_at_time(double t, double x) {
  PoseSample p;
  p.time = t;
  p.position = {x, 0, 0};
  return p;
}

}  // namespace

TEST_CASE("the stream reports a device that disappears and returns, and loses nothing complete") {
  Emulator emu;
  emu.frames(5, 0);
  auto half = emu.frame(20);  // the cable is pulled in the middle of this frame
  emu.chunks.push_back({LinkStatus::data, emu.ns, std::vector<std::uint8_t>(half.begin(), half.begin() + 30), {}});
  emu.status(LinkStatus::disconnected);
  emu.ns += 2000 * kMs;
  emu.status(LinkStatus::reconnected);
  emu.sequence = 0;  // the device restarted
  emu.frames(5, 0);
  StreamStats stats;
  auto events = run_stream(emu.chunks, 0, &stats);
  std::vector<std::string> kinds;
  for (const auto& e : events) kinds.push_back(e.status == LinkStatus::data ? "f" : to_string(e.status));
  CHECK(kinds == std::vector<std::string>{"f", "f", "f", "f", "f", "disconnected", "reconnected", "f", "f", "f", "f",
                                          "f", "ended"});
  CHECK(stats.disconnects == 1);
  CHECK(stats.reconnects == 1);
  CHECK(stats.parser.partial_dropped == 30);
  CHECK(stats.parser.frames_missing == 0);
}

TEST_CASE("replay at recorded speed keeps the pace and reports a pause as idle") {
  Emulator emu;
  emu.frames(3, 0);
  emu.ns += 250 * kMs;  // the sensor paused for a quarter second
  emu.frames(3, 0);
  const auto start = monotonic_ns();
  StreamStats stats;
  StreamOptions o;
  o.rows = o.cols = 6;
  o.read_timeout = std::chrono::milliseconds(50);
  std::vector<SensorEvent> events;
  {
    SensorStream stream(std::make_unique<ReplayTransport>(emu.chunks, 1.0), o);
    while (auto e = stream.next(std::chrono::seconds(5))) events.push_back(std::move(*e));
    stats = stream.stats();
  }
  const double elapsed_ms = static_cast<double>(monotonic_ns() - start) / kMs;
  CHECK(events.size() == 7);
  CHECK(elapsed_ms >= 250);
  CHECK(stats.idle_timeouts >= 3);
  // Frames keep their recorded times whatever the replay speed.
  CHECK(events[3].frame.host_ns - events[2].frame.host_ns == 251 * kMs);
}

TEST_CASE("a contact settles into one reading with the interpolated pose of its last frame") {
  Emulator emu;
  SettleRule rule;
  rule.frames = 4;
  ReadingFormer former(emu.calibration, rule);
  FrameParser parser(6, 6);
  auto feed = [&](int n, float kpa) {
    for (int i = 0; i < n; ++i, emu.ns += kMs) {
      parser.push(emu.frame(kpa), emu.ns);
      while (auto f = parser.next()) former.add_frame(*f);
    }
  };
  former.add_pose(pose_at_time(0.9, 0.0));
  former.add_pose(pose_at_time(1.1, 1.0));
  feed(3, 0);      // unloaded: t = 1.000 .. 1.002
  feed(2, 5);      // pressing, still rising
  feed(6, 10);     // held: settles on the 4th frame at t = 1.008
  feed(3, 10.5f);  // still in contact: no second reading
  auto readings = former.take_readings();
  REQUIRE(readings.size() == 1);
  CHECK(readings[0].time == Approx(1.008));
  CHECK(readings[0].reading.time_s == readings[0].time);  // the reading carries when its contact settled
  CHECK(readings[0].reading.position.x == Approx(0.54));
  CHECK(readings[0].reading.pressure[0] == Approx(10.0f).margin(0.01));
  CHECK(readings[0].reading.status == sva::ControllerStatus::converged);
  feed(2, 0);   // release
  feed(5, 10);  // a second contact
  CHECK(former.take_readings().size() == 1);
}

TEST_CASE("no reading forms across a dropped or corrupted frame, a saturated image or a lost link") {
  Emulator emu;
  SettleRule rule;
  rule.frames = 4;
  ReadingFormer former(emu.calibration, rule);
  former.add_pose(pose_at_time(0.0, 0.0));
  former.add_pose(pose_at_time(100.0, 0.0));
  FrameParser parser(6, 6);
  auto feed = [&](std::vector<std::uint8_t> bytes) {
    parser.push(bytes, emu.ns);
    emu.ns += kMs;
    while (auto f = parser.next()) former.add_frame(*f);
  };
  for (int i = 0; i < 3; ++i) feed(emu.frame(10));
  auto corrupted = emu.frame(10);
  corrupted[12] ^= 0x01;
  feed(corrupted);
  for (int i = 0; i < 3; ++i) feed(emu.frame(10));
  CHECK(former.take_readings().empty());  // 3 + 3 good frames around a lost one: never 4 consecutive
  former.link_lost(2.0);
  CHECK(former.take_notes().size() == 1);
  for (int i = 0; i < 3; ++i) feed(emu.frame(10));
  auto saturating = emu.calibration;
  saturating.saturation_counts = 1000 + 1000;  // 10 kPa at element 7 reads 15 kPa = 2500 counts
  ReadingFormer strict(saturating, rule);
  strict.add_pose(pose_at_time(0.0, 0.0));
  for (int i = 0; i < 6; ++i) {
    parser.push(emu.frame(10), emu.ns);
    while (auto f = parser.next()) strict.add_frame(*f);
  }
  CHECK(strict.take_readings().empty());
  CHECK_THAT(strict.take_notes().at(0).text, Contains("saturated"));
}

TEST_CASE("a lagging pose stream delays the reading, one that ends early drops it with a note") {
  Emulator emu;
  SettleRule rule;
  rule.frames = 3;
  ReadingFormer former(emu.calibration, rule);
  FrameParser parser(6, 6);
  former.add_pose(pose_at_time(0.9, 2.0));
  for (int i = 0; i < 3; ++i, emu.ns += kMs) {
    parser.push(emu.frame(10), emu.ns);
    while (auto f = parser.next()) former.add_frame(*f);
  }
  CHECK(former.take_readings().empty());
  CHECK(former.pending() == 1);
  former.add_pose(pose_at_time(1.1, 2.0));  // the arm's pose arrives late
  auto r = former.take_readings();
  REQUIRE(r.size() == 1);
  CHECK(r[0].reading.position.x == 2.0);  // the arm held still: exactly its pose
  for (int i = 0; i < 3; ++i, emu.ns += kMs) {
    parser.push(emu.frame(0), emu.ns);
    while (auto f = parser.next()) former.add_frame(*f);
  }
  emu.ns += 200 * kMs;  // the next contact comes after the last pose
  for (int i = 0; i < 3; ++i, emu.ns += kMs) {
    parser.push(emu.frame(10), emu.ns);
    while (auto f = parser.next()) former.add_frame(*f);
  }
  CHECK(former.pending() == 1);
  former.poses_ended();
  CHECK(former.take_readings().empty());
  CHECK_THAT(former.take_notes().at(0).text, Contains("pose stream ended"));
  CHECK_THROWS_WITH(former.add_pose(pose_at_time(0.5, 0)), Contains("earlier"));
}

TEST_CASE("pose lines are parsed with clear errors") {
  auto p = parse_pose_line(
      R"({"time": 1.5, "position": [1,2,3], "normal": [0,0,1], "x_axis": [1,0,0], "status": "not_converged"})", "s");
  CHECK(p.time == 1.5);
  CHECK(p.position.z == 3);
  CHECK(p.status == sva::ControllerStatus::not_converged);
  CHECK(parse_pose_line(pose_line(p), "again").position == p.position);
  CHECK_THROWS_WITH(parse_pose_line("{\"time\": 1}", "poses.jsonl:3"), Contains("poses.jsonl:3"));
  CHECK_THROWS_WITH(parse_pose_line(R"({"time": 1, "position": [0,0,0], "normal": [0,0,2], "x_axis": [1,0,0]})", "p"),
                    Contains("unit"));
  CHECK_THROWS_WITH(parse_pose_line("not json", "p:9"), Contains("p:9"));
}

TEST_CASE("USB: device selectors, and the errors that need no device") {
  auto serial = DeviceSelector::parse("A12B");
  CHECK(serial.serial == "A12B");
  auto ids = DeviceSelector::parse("16c0:05dc");
  CHECK(ids.vendor_id == 0x16c0);
  CHECK(ids.product_id == 0x05dc);
  auto port = DeviceSelector::parse("3-1.2");
  CHECK(port.bus == 3);
  CHECK(port.ports == std::vector<int>{1, 2});
  CHECK_THROWS_WITH(DeviceSelector::parse("zz:1"), Contains("hex"));
  CHECK_THROWS_WITH(DeviceSelector::parse("3-x"), Contains("BUS-PORT"));
  CHECK_THROWS_WITH(DeviceSelector::parse(""), Contains("empty"));

  UsbOptions out_endpoint;
  out_endpoint.device = ids;
  out_endpoint.endpoint = 0x01;
  CHECK_THROWS_WITH(UsbTransport(out_endpoint), Contains("OUT endpoint"));

  UsbOptions absent;
  absent.device = DeviceSelector::parse("dead:beef");
  try {
    UsbTransport t(absent);
    FAIL("no device should be found");
  } catch (const sva::Error& e) {
    std::string m = e.what();
    CHECK((m.find("dead:beef") != std::string::npos || m.find("USB unavailable") != std::string::npos));
  }
  // libusb's codes: -3 access denied, -6 busy, -4 no device.
  CHECK_THAT(describe_usb_error(-3, "opening bus 1 device 4", "serial A12"),
             Contains("serial A12") && Contains("udev"));
  CHECK_THAT(describe_usb_error(-6, "claiming interface 0", "x"), Contains("another program"));
  CHECK_THAT(describe_usb_error(-4, "reading", "x"), Contains("unplugged"));
}

TEST_CASE("USB reconnect: hotplug events where libusb has them, else polling, and the status says which") {
  using namespace std::chrono_literals;
  // The decision: hotplug only when wanted, offered by the platform, and the callback registered.
  const auto hot = plan_reconnect(true, true, 0, 500ms);
  CHECK(hot.mode == ReconnectMode::hotplug);
  CHECK_THAT(hot.message, Contains("hotplug"));
  const auto unsupported = plan_reconnect(true, false, 0, 500ms);
  CHECK(unsupported.mode == ReconnectMode::polling);
  CHECK_THAT(unsupported.message, Contains("polling every 500 ms") && Contains("no hotplug support"));
  // libusb's -12: LIBUSB_ERROR_NOT_SUPPORTED.
  const auto failed = plan_reconnect(true, true, -12, 250ms);
  CHECK(failed.mode == ReconnectMode::polling);
  CHECK_THAT(failed.message, Contains("polling every 250 ms") && Contains("LIBUSB_ERROR_NOT_SUPPORTED"));
  const auto off = plan_reconnect(false, true, 0, 500ms);
  CHECK(off.mode == ReconnectMode::polling);
  CHECK_THAT(off.message, Contains("turned off"));

  // The same decision made against this machine's libusb, registering and removing the real callback (no device
  // needed): hotplug exactly where libusb reports the capability.
  UsbOptions options;
  options.device = DeviceSelector::parse("16c0:05dc");
  try {
    const auto here = usb_reconnect_plan(options);
    CHECK((here.mode == ReconnectMode::hotplug) == usb_has_hotplug());
    options.hotplug = false;
    CHECK(usb_reconnect_plan(options).mode == ReconnectMode::polling);
    options.hotplug = true;
    options.device = DeviceSelector::parse("A12B");  // a serial: any vendor's arrival wakes it, the serial is checked
    CHECK((usb_reconnect_plan(options).mode == ReconnectMode::hotplug) == usb_has_hotplug());
  } catch (const sva::Error& e) {
    CHECK_THAT(e.what(), Contains("USB unavailable"));  // a container without USB: the error path, named
  }
}
