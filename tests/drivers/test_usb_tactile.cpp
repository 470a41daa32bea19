#include <catch2/catch.hpp>

#include <sva/drivers/usb_tactile.hpp>
#include <sva/error.hpp>

#include <fstream>

#include "test_support.hpp"

using namespace sva::drivers;
using Catch::Contains;

TEST_CASE("tactile frames round-trip and every corruption is refused") {
  TactileFrame f;
  f.rows = 6;
  f.cols = 6;
  f.sequence = 513;
  for (int i = 0; i < 36; ++i) f.counts.push_back(static_cast<std::uint16_t>(1000 + 37 * i));
  auto bytes = encode_frame(f);
  auto back = parse_frame(bytes);
  CHECK(back.counts == f.counts);
  CHECK(back.sequence == 513);
  auto flipped = bytes;
  flipped[10] ^= 1;
  CHECK_THROWS_WITH(parse_frame(flipped), Contains("CRC"));
  CHECK_THROWS_WITH(parse_frame(std::span(bytes).first(bytes.size() - 1)), Contains("expected"));
  auto magic = bytes;
  magic[0] = 'X';
  CHECK_THROWS_WITH(parse_frame(magic), Contains("magic"));
  CHECK_THROWS_WITH(parse_frame(std::span(bytes).first(3)), Contains("shorter"));
  CHECK(crc16_ccitt(std::vector<std::uint8_t>{'1', '2', '3', '4', '5', '6', '7', '8', '9'}) ==
        0x29B1);  // CRC-16/CCITT-FALSE check value
}

TEST_CASE("calibration maps counts to kPa and validates its file") {
  sva::SensorSpec s;
  auto c = Calibration::uniform(s, 0.5f, 100.0f);
  TactileFrame f{0, 6, 6, std::vector<std::uint16_t>(36, 140)};
  f.counts[0] = 50;  // below zero load: clamps to 0
  auto p = c.to_pressure(f);
  CHECK(p[0] == 0.0f);
  CHECK(p[1] == Approx(20.0f));
  TactileFrame small{0, 4, 4, std::vector<std::uint16_t>(16, 0)};
  CHECK_THROWS_WITH(c.to_pressure(small), Contains("4 x 4"));
  auto dir = sva::test::temp_dir("calib");
  std::ofstream(dir / "bad.json")
      << R"({"rows": 2, "cols": 2, "pitch_mm": 2, "gain_kpa_per_count": [1, 1, 1], "zero_counts": [0, 0, 0, 0]})";
  CHECK_THROWS_WITH(Calibration::load(dir / "bad.json"), Contains("bad.json") && Contains("rows*cols"));
  std::ofstream(dir / "ok.json")
      << R"({"rows": 1, "cols": 2, "pitch_mm": 2, "gain_kpa_per_count": [1, 2], "zero_counts": [0, 1]})";
  auto ok = Calibration::load(dir / "ok.json");
  CHECK(ok.to_pressure(TactileFrame{0, 1, 2, {5, 5}}) == std::vector<float>{5.0f, 8.0f});
  CHECK_THROWS_WITH(Calibration::load(dir / "missing.json"), Contains("missing.json"));
}

TEST_CASE("opening an absent sensor is a clear error, not a crash") {
  UsbSensorOptions o;
  o.vendor_id = 0xdead;
  o.product_id = 0xbeef;
  try {
    UsbTactileSensor sensor(o, Calibration::uniform({}, 1.0f, 0.0f));
    FAIL("no device should be found");
  } catch (const sva::Error& e) {
    std::string m = e.what();
    CHECK((m.find("dead:beef") != std::string::npos || m.find("USB unavailable") != std::string::npos));
  }
}
