// The wire format, the resynchronising parser, the calibration and the ring
// buffer: the parts of the driver that see bytes, without a device.
#include <catch2/catch.hpp>

#include <sva/drivers/calibration.hpp>
#include <sva/drivers/frame.hpp>
#include <sva/drivers/ring_buffer.hpp>
#include <sva/error.hpp>

#include <fstream>
#include <random>

#include "test_support.hpp"

using namespace sva::drivers;
using Catch::Contains;

namespace {

TactileFrame make_frame(std::uint16_t sequence, int rows = 6, int cols = 6) {
  TactileFrame f{sequence, rows, cols, {}};
  for (int i = 0; i < rows * cols; ++i) f.counts.push_back(static_cast<std::uint16_t>(1000 + 37 * i + sequence));
  return f;
}

std::vector<StreamFrame> drain(FrameParser& p) {
  std::vector<StreamFrame> out;
  while (auto f = p.next()) out.push_back(std::move(*f));
  return out;
}

}  // namespace

TEST_CASE("tactile frames round-trip and every corruption is refused") {
  auto f = make_frame(513);
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
  TactileFrame wrong{0, 2, 2, {1, 2, 3}};
  CHECK_THROWS_WITH(encode_frame(wrong), Contains("3 counts"));
}

TEST_CASE("the parser finds every frame however transfers split and merge them") {
  std::vector<std::uint8_t> stream;
  std::vector<TactileFrame> sent;
  for (std::uint16_t s = 65500; sent.size() < 200; ++s) {  // crosses the u16 wrap of the sequence number
    sent.push_back(make_frame(s));
    auto b = encode_frame(sent.back());
    stream.insert(stream.end(), b.begin(), b.end());
  }
  std::mt19937 rng(7);
  FrameParser parser(6, 6);
  std::vector<StreamFrame> got;
  for (std::size_t at = 0, n = 0; at < stream.size(); at += n) {
    n = std::min<std::size_t>(stream.size() - at, std::uniform_int_distribution<std::size_t>(1, 300)(rng));
    parser.push(std::span(stream).subspan(at, n), static_cast<std::int64_t>(at));
    for (auto& f : drain(parser)) got.push_back(std::move(f));
  }
  REQUIRE(got.size() == sent.size());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    CHECK(got[i].frame.sequence == sent[i].sequence);
    CHECK(got[i].frame.counts == sent[i].counts);
    CHECK(got[i].missing_before == 0);
    // Stamped with the transfer (here: its offset) that held the frame's last byte.
    const auto end = static_cast<std::int64_t>((i + 1) * frame_bytes(6, 6));
    CHECK((got[i].host_ns < end && got[i].host_ns + 300 >= end));
  }
  CHECK(parser.stats().bytes_skipped == 0);
  CHECK(parser.stats().sequence_gaps == 0);
}

TEST_CASE("corrupted bytes are skipped to the next valid frame and a dropped frame is counted") {
  std::vector<std::uint8_t> stream = {0x00, 'S', 'T', 0xff};  // noise, including a false magic
  for (std::uint16_t s = 0; s < 10; ++s) {
    if (s == 4) continue;  // the device dropped frame 4
    auto b = encode_frame(make_frame(s));
    if (s == 6) b[20] ^= 0x40;                                     // frame 6 corrupted in transfer
    if (s == 8) stream.insert(stream.end(), {'S', 'T', 6, 6, 0});  // a truncated header before frame 8
    stream.insert(stream.end(), b.begin(), b.end());
  }
  FrameParser parser(6, 6);
  parser.push(stream, 5);
  auto got = drain(parser);
  std::vector<int> sequences;
  for (const auto& f : got) sequences.push_back(f.frame.sequence);
  CHECK(sequences == std::vector<int>{0, 1, 2, 3, 5, 7, 8, 9});  // nothing complete lost, nothing corrupted kept
  CHECK(got[4].missing_before == 1);
  CHECK(got[5].missing_before == 1);
  const auto& s = parser.stats();
  CHECK(s.crc_errors >= 1);
  CHECK(s.frames_missing == 2);  // frame 4 (dropped) and frame 6 (corrupted)
  CHECK(s.sequence_gaps == 2);
  CHECK(s.bytes_skipped == 4 + frame_bytes(6, 6) + 5);
}

TEST_CASE("a reset after a disconnect drops the partial frame and restarts the sequence") {
  FrameParser parser(6, 6);
  auto a = encode_frame(make_frame(10)), b = encode_frame(make_frame(0));
  parser.push(std::span(a).first(20), 1);
  CHECK_FALSE(parser.next());
  parser.reset();
  CHECK(parser.stats().partial_dropped == 20);
  parser.push(b, 2);
  auto f = parser.next();
  REQUIRE(f);
  CHECK(f->frame.sequence == 0);
  CHECK(f->missing_before == 0);  // a restarted device is not a gap
  CHECK(f->host_ns == 2);
}

TEST_CASE("calibration maps counts to kPa, tares, flags saturation and validates its file") {
  sva::SensorSpec s;
  auto c = Calibration::uniform(s, 0.5f, 100.0f);
  TactileFrame f{0, 6, 6, std::vector<std::uint16_t>(36, 140)};
  f.counts[0] = 50;  // below zero load: clamps to 0
  auto p = c.to_pressure(f);
  CHECK(p[0] == 0.0f);
  CHECK(p[1] == Approx(20.0f));
  CHECK(c.saturated(f) == 0);
  c.saturation_counts = 140;
  CHECK(c.saturated(f) == 35);
  TactileFrame small{0, 4, 4, std::vector<std::uint16_t>(16, 0)};
  CHECK_THROWS_WITH(c.to_pressure(small), Contains("4 x 4"));

  std::vector<TactileFrame> unloaded{f, f};
  unloaded[1].counts.assign(36, 150);
  c.tare(unloaded);
  CHECK(c.zero[0] == 100.0f);  // (50 + 150) / 2
  CHECK(c.zero[1] == 145.0f);
  CHECK_THROWS_WITH(c.tare({}), Contains("no unloaded frames"));

  auto e = Calibration::uniform(s, 0.01f, 1000.0f);
  std::vector<float> pressure(36, 12.34f);
  pressure[3] = 0.0f;
  TactileFrame encoded{0, 6, 6, e.to_counts(pressure)};
  auto decoded = e.to_pressure(encoded);
  for (std::size_t i = 0; i < 36; ++i) CHECK(std::abs(decoded[i] - pressure[i]) <= 0.005f + 1e-5f);

  auto dir = sva::test::temp_dir("calib");
  std::ofstream(dir / "bad.json")
      << R"({"rows": 2, "cols": 2, "pitch_mm": 2, "gain_kpa_per_count": [1, 1, 1], "zero_counts": [0, 0, 0, 0]})";
  CHECK_THROWS_WITH(Calibration::load(dir / "bad.json"), Contains("bad.json") && Contains("rows*cols"));
  std::ofstream(dir / "ok.json")
      << R"({"rows": 1, "cols": 2, "pitch_mm": 2, "gain_kpa_per_count": [1, 2], "zero_counts": [0, 1]})";
  auto ok = Calibration::load(dir / "ok.json");
  CHECK(ok.to_pressure(TactileFrame{0, 1, 2, {5, 5}}) == std::vector<float>{5.0f, 8.0f});
  CHECK(Calibration::from_json(ok.to_json(), "round trip").zero == ok.zero);
  CHECK_THROWS_WITH(Calibration::load(dir / "missing.json"), Contains("missing.json"));
}

TEST_CASE("the ring buffer is bounded, counts what it refuses and wakes a waiting consumer") {
  RingBuffer<int> ring(3);
  CHECK(ring.try_push(1));
  CHECK(ring.try_push(2));
  CHECK(ring.try_push(3));
  CHECK_FALSE(ring.try_push(4));
  CHECK(ring.overflows() == 1);
  CHECK(ring.pop(std::chrono::milliseconds(1)) == 1);
  CHECK(ring.try_push(5));
  CHECK(ring.pop(std::chrono::milliseconds(1)) == 2);
  CHECK(ring.pop(std::chrono::milliseconds(1)) == 3);
  CHECK(ring.pop(std::chrono::milliseconds(1)) == 5);
  CHECK_FALSE(ring.pop(std::chrono::milliseconds(1)));
  std::thread producer([&] {
    for (int i = 0; i < 1000; ++i) ring.push_wait(i);
    ring.close();
  });
  int expected = 0;
  while (auto v = ring.pop(std::chrono::seconds(5))) CHECK(*v == expected++);
  producer.join();
  CHECK(expected == 1000);
  CHECK(ring.closed_and_empty());
}
