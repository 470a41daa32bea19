// Session recordings: the file format survives a crash, and a simulated
// dataset exported as a recording replays to the direct path's estimates, bit
// for bit.
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include <sva/batch_file.hpp>
#include <sva/io/recording_file.hpp>
#include "test_support.hpp"

using namespace sva::drivers;
using Catch::Contains;
using sva::io::RecordType;

namespace {

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

// Simulates and trains the tiny built-in scene once per test process.
std::filesystem::path tiny_world() {
  static const std::filesystem::path dir = [] {
    auto d = sva::test::temp_dir("session");
    std::string out;
    REQUIRE(sva::test::run_sva("simulate --scene tiny --out " + d.string() + " --seed 5", &out) == 0);
    REQUIRE(sva::test::run_sva("train --data " + (d / "train.svad").string() + " --out " + (d / "map.svam").string(),
                               &out) == 0);
    return d;
  }();
  return dir;
}

bool same(const sva::Estimate& a, const sva::Estimate& b) {
  return a.readings == b.readings && a.object == b.object && a.object_probability == b.object_probability &&
         a.pose.R == b.pose.R && a.pose.T == b.pose.T && a.top.size() == b.top.size();
}

}  // namespace

TEST_CASE("a recording is valid up to its last complete record and can be appended to") {
  const auto dir = sva::test::temp_dir("recording");
  const auto file = dir / "s.svar";
  {
    sva::io::RecordingWriter w(file, false);
    w.write(RecordType::note, bytes_of("one"));
    w.write(RecordType::note, bytes_of("two"));
  }
  const auto full = std::filesystem::file_size(file);
  auto c = sva::io::read_recording(file);
  REQUIRE(c.records.size() == 2);
  CHECK(c.tail_problem.empty());
  CHECK(c.valid_bytes == full);

  std::filesystem::resize_file(file, full - 3);  // a crash while writing the last record
  c = sva::io::read_recording(file);
  CHECK(c.records.size() == 1);
  CHECK_THAT(c.tail_problem, Contains("truncated"));
  {
    sva::io::RecordingWriter w(file, true);  // continues after cutting the partial record
    w.write(RecordType::note, bytes_of("three"));
  }
  c = sva::io::read_recording(file);
  REQUIRE(c.records.size() == 2);
  CHECK(c.tail_problem.empty());
  CHECK(std::string(c.records[1].payload.begin(), c.records[1].payload.end()) == "three");

  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(16 + 8 + 1);  // inside the first record's payload
    f.put('X');
  }
  c = sva::io::read_recording(file);
  CHECK(c.records.empty());
  CHECK_THAT(c.tail_problem, Contains("checksum"));

  std::ofstream(dir / "not.svar") << "hello, this is not a recording";
  CHECK_THROWS_WITH(sva::io::read_recording(dir / "not.svar"), Contains("not.svar") && Contains("magic"));
  CHECK_THROWS_WITH(load_session(file), Contains("settings"));
  CHECK_THROWS_WITH(load_session(dir / "missing.svar"), Contains("missing.svar"));
}

TEST_CASE("a simulated session exported as a recording replays to the direct path's estimates, bit for bit") {
  const auto d = tiny_world();
  auto data = sva::load_dataset(d / "test.svad");
  data.samples.resize(std::min<std::size_t>(data.samples.size(), 10));
  const auto map = sva::Map::load(d / "map.svam");
  const auto calibration = export_calibration(data.scene.sensor);
  const auto file = d / "test.svar";
  export_dataset_session(data, calibration, 5.0, 200.0, file);

  // Direct path: the dataset's converged readings as the sensor reports them (its counts, then kPa).
  sva::Recognizer direct(map, map.pose_space());
  std::vector<sva::Estimate> expected;
  std::vector<sva::Reading> direct_readings;
  for (const auto& s : data.samples) {
    if (s.reading.status == sva::ControllerStatus::no_contact) continue;
    sva::Reading r = s.reading;
    r.pressure = calibration.to_pressure(
        TactileFrame{0, data.scene.sensor.rows, data.scene.sensor.cols, calibration.to_counts(r.pressure)});
    direct_readings.push_back(r);
    if (r.status != sva::ControllerStatus::converged) continue;
    direct.add_reading(r);
    expected.push_back(direct.estimate());
  }
  REQUIRE(expected.size() >= 3);

  const auto session = load_session(file);
  CHECK(session.tail_problem.empty());
  sva::Recognizer replayed(map, map.pose_space());
  std::vector<sva::Estimate> got;
  std::vector<sva::Reading> formed;
  PipelineEvents events;
  events.on_reading = [&](const FormedReading& f, std::int64_t) {
    formed.push_back(f.reading);
    if (f.reading.status != sva::ControllerStatus::converged) return;
    replayed.add_reading(f.reading);
    got.push_back(replayed.estimate());
  };
  std::vector<std::string> notes;
  events.on_note = [&](const ContactNote& n) { notes.push_back(n.text); };
  const auto stats = replay_session(session, 0.0, events);
  CHECK(notes.empty());
  CHECK(stats.parser.crc_errors == 0);
  REQUIRE(formed.size() == direct_readings.size());
  for (std::size_t i = 0; i < formed.size(); ++i) {
    CHECK(formed[i].position == direct_readings[i].position);
    CHECK(formed[i].normal == direct_readings[i].normal);
    CHECK(formed[i].x_axis == direct_readings[i].x_axis);
    CHECK(formed[i].pressure == direct_readings[i].pressure);
    CHECK(formed[i].status == direct_readings[i].status);
  }
  REQUIRE(got.size() == expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) CHECK(same(got[i], expected[i]));
}

TEST_CASE("sva export --recording and sva replay: readings and estimates on stdout, problems named") {
  const auto d = tiny_world();
  std::string out;
  const auto rec = (d / "cli.svar").string();
  REQUIRE(sva::test::run_sva("export --data " + (d / "test.svad").string() + " --recording " + rec +
                                 " --touch-rate 10 --frame-rate 100",
                             &out) == 0);
  REQUIRE(sva::test::run_sva("replay " + rec + " --speed 0 --map " + (d / "map.svam").string(), &out) == 0);
  CHECK_THAT(out, Contains("\"type\":\"reading\"") && Contains("\"type\":\"estimate\"") && Contains("worst latency"));
  // --write-session: the converged readings as a sessions file, with their times, for sva recognize and sva.ros.
  const auto written = (d / "replayed.jsonl").string();
  REQUIRE(sva::test::run_sva("replay " + rec + " --speed 0 --write-session " + written, &out) == 0);
  const auto sessions = sva::read_batch_sessions(written, 36);
  REQUIRE(sessions.size() == 1);
  CHECK(sessions[0].readings.size() >= 3);
  const auto truth = nlohmann::json::parse(sessions[0].truth);
  CHECK(truth["stamps_s"].size() == sessions[0].readings.size());
  CHECK(truth["recording"] == rec);
  REQUIRE(sva::test::run_sva("recognize --map " + (d / "map.svam").string() + " --batch " + written + " --out " +
                                 (d / "replayed_results.jsonl").string() + " --backend cpu",
                             &out) == 0);
  // The export's touches start unloaded (zero at 1000 counts): a tare from its first frames finds that zero.
  const auto cal = (d / "cal.json").string();
  REQUIRE(sva::test::run_sva("calibrate --session " + rec + " --frames 3 --gain 0.01 --out " + cal, &out) == 0);
  const auto tared = Calibration::load(cal);
  CHECK(tared.zero == std::vector<float>(36, 1000.0f));
  CHECK(tared.gain == std::vector<float>(36, 0.01f));
  CHECK(sva::test::run_sva("calibrate --session " + rec + " --frames 100000 --out " + cal, &out) == 1);
  CHECK_THAT(out, Contains("link ended") && Contains("of 100000"));
  CHECK(sva::test::run_sva("calibrate --out " + cal, &out) == 1);
  CHECK_THAT(out, Contains("exactly one of --device, --session"));
  // A crash mid-record: everything before it replays, and the user is told.
  std::filesystem::resize_file(rec, std::filesystem::file_size(rec) - 10);
  REQUIRE(sva::test::run_sva("replay " + rec + " --speed 0", &out) == 0);
  CHECK_THAT(out, Contains("ends early") && Contains("\"type\":\"reading\""));
  CHECK(sva::test::run_sva("replay " + (d / "map.svam").string(), &out) == 1);
  CHECK_THAT(out, Contains("map.svam") && Contains("not an sva recording"));
  CHECK(sva::test::run_sva("replay " + rec + " --speed -1", &out) != 0);
  CHECK(sva::test::run_sva("record --device dead:beef --calibration nope.json --poses - --out x.svar", &out) == 1);
  CHECK_THAT(out, Contains("nope.json"));
  CHECK(sva::test::run_sva(
            "export --data " + (d / "test.svad").string() + " --recording " + rec + " --touch-rate 50 --frame-rate 100",
            &out) == 1);
  CHECK_THAT(out, Contains("frames per touch"));
}

TEST_CASE("the whole chain: split, merged and corrupted transfers lose only the touch whose frame was corrupted") {
  const auto d = tiny_world();
  auto data = sva::load_dataset(d / "test.svad");
  data.samples.resize(std::min<std::size_t>(data.samples.size(), 6));
  const auto file = d / "chain.svar";
  export_dataset_session(data, export_calibration(data.scene.sensor), 10.0, 100.0, file);
  const auto clean = load_session(file);
  auto collect = [](const Session& s, std::vector<std::string>* notes = nullptr) {
    std::vector<FormedReading> out;
    PipelineEvents events;
    events.on_reading = [&](const FormedReading& f, std::int64_t) { out.push_back(f); };
    events.on_note = [&](const ContactNote& n) {
      if (notes) notes->push_back(n.text);
    };
    replay_session(s, 0.0, events);
    return out;
  };
  const auto expected = collect(clean);
  REQUIRE(expected.size() == data.samples.size());

  // The same bytes in transfers of 1..80 bytes (up to a frame: a frame's time, that of the transfer completing it,
  // moves by at most one frame), one byte corrupted in the third touch's settle window.
  Session rechunked = clean;
  rechunked.chunks.clear();
  std::vector<std::uint8_t> all;
  std::vector<std::int64_t> time_of_byte;
  for (const auto& c : clean.chunks) {
    all.insert(all.end(), c.bytes.begin(), c.bytes.end());
    time_of_byte.insert(time_of_byte.end(), c.bytes.size(), c.host_ns);
  }
  const std::size_t frame = frame_bytes(data.scene.sensor.rows, data.scene.sensor.cols);
  all[(2 * 10 + 7) * frame + 20] ^= 0x10;  // touch 2 (10 frames each), the 4th of its 6 held frames
  std::uint32_t state = 12345;
  for (std::size_t at = 0, n = 0; at < all.size(); at += n) {
    state = state * 1664525u + 1013904223u;
    n = std::min<std::size_t>(all.size() - at, 1 + (state >> 8) % frame);
    // A transfer completes when its last byte arrived.
    rechunked.chunks.push_back({LinkStatus::data,
                                time_of_byte[at + n - 1],
                                std::vector<std::uint8_t>(all.begin() + static_cast<std::ptrdiff_t>(at),
                                                          all.begin() + static_cast<std::ptrdiff_t>(at + n)),
                                {}});
  }
  const auto got = collect(rechunked);
  REQUIRE(got.size() == expected.size() - 1);
  for (std::size_t i = 0, j = 0; i < expected.size(); ++i) {
    if (i == 2) continue;  // never formed from (or across) the corrupted frame
    CHECK(got[j].reading.pressure == expected[i].reading.pressure);
    CHECK(got[j].reading.position == expected[i].reading.position);
    CHECK(std::abs(got[j].time - expected[i].time) <= 0.0100001);
    ++j;
  }
}

TEST_CASE("recording live (an emulated sensor and a pose file) writes a session that replays to the same readings") {
  const auto d = tiny_world();
  auto data = sva::load_dataset(d / "test.svad");
  data.samples.resize(std::min<std::size_t>(data.samples.size(), 4));
  export_dataset_session(data, export_calibration(data.scene.sensor), 10.0, 100.0, d / "source.svar");
  const auto source = load_session(d / "source.svar");
  {
    std::ofstream poses(d / "poses.jsonl");
    for (const auto& p : source.poses) poses << pose_line(p.pose) << "\n";
    poses << "{\"time\": \"late\"}\n";  // a bad line: skipped with a note naming it
  }
  PoseStream poses((d / "poses.jsonl").string());
  SessionWriter writer(d / "live.svar", source.settings);
  LiveOptions live{source.settings, &writer};
  std::vector<FormedReading> formed;
  std::vector<std::string> notes;
  PipelineEvents events;
  events.on_reading = [&](const FormedReading& f, std::int64_t) { formed.push_back(f); };
  events.on_note = [&](const ContactNote& n) { notes.push_back(n.text); };
  // The emulated sensor plays at 4x the recorded pace, so the pose file has been read long before the frames end.
  run_live(std::make_unique<ReplayTransport>(source.chunks, 4.0), poses, live, events);
  CHECK(formed.size() == data.samples.size());
  REQUIRE(notes.size() == 1);
  CHECK_THAT(notes[0], Contains("poses.jsonl:" + std::to_string(source.poses.size() + 1)));

  const auto recorded = load_session(d / "live.svar");
  CHECK(recorded.readings.size() == formed.size());
  CHECK(recorded.poses.size() == source.poses.size());
  CHECK(recorded.notes.size() == 1);
  std::vector<FormedReading> replayed;
  PipelineEvents again;
  again.on_reading = [&](const FormedReading& f, std::int64_t) { replayed.push_back(f); };
  replay_session(recorded, 0.0, again);
  REQUIRE(replayed.size() == formed.size());
  for (std::size_t i = 0; i < formed.size(); ++i) {
    CHECK(replayed[i].reading.pressure == formed[i].reading.pressure);
    CHECK(replayed[i].reading.position == formed[i].reading.position);
    CHECK(replayed[i].time == formed[i].time);
  }
}

TEST_CASE("a pose clock offset matches an arm's poses on another clock, the wrong one misses them") {
  const auto d = tiny_world();
  auto data = sva::load_dataset(d / "test.svad");
  data.samples.resize(std::min<std::size_t>(data.samples.size(), 6));
  export_dataset_session(data, export_calibration(data.scene.sensor), 5.0, 200.0, d / "clock.svar");
  const auto on_host_clock = load_session(d / "clock.svar");
  auto formed_by = [](const Session& s, std::vector<std::string>* notes) {
    std::vector<sva::Reading> out;
    PipelineEvents events;
    events.on_reading = [&](const FormedReading& f, std::int64_t) { out.push_back(f.reading); };
    events.on_note = [&](const ContactNote& n) { notes->push_back(n.text); };
    replay_session(s, 0.0, events);
    return out;
  };
  std::vector<std::string> notes;
  const auto expected = formed_by(on_host_clock, &notes);
  REQUIRE(expected.size() >= 3);
  REQUIRE(notes.empty());

  // The arm's clock runs 1234.5 s behind the host's: its pose times are that much smaller (arrival unchanged).
  Session arm_clock = on_host_clock;
  for (auto& p : arm_clock.poses) p.pose.time -= 1234.5;
  const auto missed = formed_by(arm_clock, &notes);
  CHECK(missed.empty());
  CHECK(notes.size() == expected.size());  // every contact dropped with a note
  if (!notes.empty()) CHECK_THAT(notes[0], Contains("dropped"));

  arm_clock.settings.settle.pose_clock_offset_s = 1234.5;
  notes.clear();
  const auto matched = formed_by(arm_clock, &notes);
  CHECK(notes.empty());
  REQUIRE(matched.size() == expected.size());
  for (std::size_t i = 0; i < matched.size(); ++i) {
    CHECK(matched[i].position == expected[i].position);
    CHECK(matched[i].normal == expected[i].normal);
    CHECK(matched[i].pressure == expected[i].pressure);
  }

  // The offset is saved with the recording's settle rule, so a replay applies it again; the CLI may override it.
  {
    SessionWriter writer(d / "offset.svar", arm_clock.settings);
    for (const auto& c : arm_clock.chunks) writer.chunk(c);
    for (const auto& p : arm_clock.poses) writer.pose(p);
  }
  CHECK(load_session(d / "offset.svar").settings.settle.pose_clock_offset_s == 1234.5);
  std::string out;
  REQUIRE(sva::test::run_sva("replay " + (d / "offset.svar").string() + " --speed 0", &out) == 0);
  CHECK_THAT(out, Contains("sva replay: " + std::to_string(expected.size()) + " readings"));
  REQUIRE(sva::test::run_sva("replay " + (d / "offset.svar").string() + " --speed 0 --pose-clock-offset 0", &out) == 0);
  CHECK_THAT(out, Contains("sva replay: 0 readings") && Contains("dropped"));
  SettleRule bad;
  bad.pose_clock_offset_s = std::nan("");
  CHECK_THROWS_WITH(bad.validate(), Contains("pose_clock_offset_s"));
}
