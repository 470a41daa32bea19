#include <sva/drivers/session.hpp>
#include <sva/error.hpp>

#include <cmath>
#include <mutex>
#include <nlohmann/json.hpp>

#include <sva/io/binary_file.hpp>
#include <sva/io/json.hpp>
#include <sva/io/recording_file.hpp>

namespace sva::drivers {

namespace {

using io::RecordType;

std::vector<std::uint8_t> settings_payload(const SessionSettings& s) {
  nlohmann::json j{{"calibration", io::parse_json(s.calibration.to_json())},
                   {"settle", io::parse_json(s.settle.to_json())},
                   {"device", s.device}};
  const std::string text = io::dump_json(j);
  return {text.begin(), text.end()};
}

SessionSettings parse_settings(const std::vector<std::uint8_t>& payload, const std::string& source) {
  const std::string_view text(reinterpret_cast<const char*>(payload.data()), payload.size());
  if (io::json_depth(text) > io::kMaxJsonDepth)
    throw Error(source + ": bad settings record: " + io::json_too_deep_message());
  try {
    const auto j = io::parse_json(text);
    SessionSettings s;
    s.calibration = Calibration::from_json(io::dump_json(j.at("calibration")), source + " (calibration)");
    s.settle = SettleRule::from_json(io::dump_json(j.at("settle")), source + " (settle rule)");
    s.device = j.value("device", "");
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": bad settings record: " + e.what());
  }
}

std::vector<std::uint8_t> chunk_payload(const Chunk& c) {
  io::BinaryWriter w;
  w.put<std::int64_t>(c.host_ns);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(c.status));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(c.message.size()));
  w.put_array(c.message.data(), c.message.size());
  w.put_array(c.bytes.data(), c.bytes.size());
  return w.bytes();
}

Chunk parse_chunk(io::BinaryReader& r) {
  Chunk c;
  c.host_ns = r.get<std::int64_t>();
  const auto status = r.get<std::uint8_t>();
  if (status > static_cast<std::uint8_t>(LinkStatus::failed)) r.fail("unknown link status " + std::to_string(status));
  c.status = static_cast<LinkStatus>(status);
  const auto n = r.get<std::uint32_t>();
  c.message.resize(n > r.remaining() ? 0 : n);
  if (n > r.remaining()) r.fail("message longer than its record");
  r.get_array(c.message.data(), n);
  c.bytes.resize(r.remaining());
  r.get_array(c.bytes.data(), c.bytes.size());
  return c;
}

std::vector<std::uint8_t> reading_payload(const FormedReading& f) {
  io::BinaryWriter w;
  w.put<double>(f.time);
  w.put<std::uint16_t>(f.sequence);
  for (const auto* v : {&f.reading.position, &f.reading.normal, &f.reading.x_axis}) w.put_array(&(*v)[0], 3);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(f.reading.status));
  w.put<std::uint16_t>(f.reading.iterations);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(f.reading.pressure.size()));
  w.put_array(f.reading.pressure.data(), f.reading.pressure.size());
  return w.bytes();
}

FormedReading parse_reading(io::BinaryReader& r) {
  FormedReading f;
  f.time = r.get<double>();
  f.sequence = r.get<std::uint16_t>();
  for (auto* v : {&f.reading.position, &f.reading.normal, &f.reading.x_axis}) r.get_array(&(*v)[0], 3);
  const auto status = r.get<std::uint8_t>();
  if (status > static_cast<std::uint8_t>(ControllerStatus::no_contact)) r.fail("unknown reading status");
  f.reading.status = static_cast<ControllerStatus>(status);
  f.reading.iterations = r.get<std::uint16_t>();
  const auto n = r.get<std::uint32_t>();
  if (n > r.remaining() / sizeof(float))
    r.fail("pressure image of " + std::to_string(n) + " values exceeds its record");
  f.reading.pressure.resize(n);
  r.get_array(f.reading.pressure.data(), f.reading.pressure.size());
  f.reading.time_s = f.time;
  r.expect_end();
  return f;
}

std::string payload_text(io::BinaryReader& r) {
  std::string s(r.remaining(), '\0');
  r.get_array(s.data(), s.size());
  return s;
}

void add_record(Session& s, const io::Record& rec, const std::string& name) {
  io::BinaryReader r(rec.payload, name);
  switch (rec.type) {
    case RecordType::settings:
      s.settings = parse_settings(rec.payload, name);
      break;
    case RecordType::chunk:
      s.chunks.push_back(parse_chunk(r));
      break;
    case RecordType::pose: {
      RecordedPose p;
      p.arrival_ns = r.get<std::int64_t>();
      p.pose = parse_pose_line(payload_text(r), name + " (pose)");
      s.poses.push_back(p);
      break;
    }
    case RecordType::reading:
      s.readings.push_back(parse_reading(r));
      break;
    case RecordType::note: {
      ContactNote n;
      n.time = r.get<double>();
      n.text = payload_text(r);
      s.notes.push_back(std::move(n));
      break;
    }
    default:
      break;  // a newer writer's record type: skipped
  }
}

}  // namespace

Session load_session(const std::filesystem::path& file) {
  const auto contents = io::read_recording(file);
  Session s;
  s.tail_problem = contents.tail_problem;
  bool have_settings = false;
  for (std::size_t i = 0; i < contents.records.size(); ++i) {
    const std::string name = file.string() + " record " + std::to_string(i);
    have_settings |= contents.records[i].type == RecordType::settings;
    if (i == 0 && !have_settings) throw Error(file.string() + ": the first record must be the settings");
    add_record(s, contents.records[i], name);
  }
  if (!have_settings) throw Error(file.string() + ": no settings record (calibration and settle rule)");
  return s;
}

struct SessionWriter::Impl {
  std::mutex mutex;
  std::unique_ptr<io::RecordingWriter> writer;
  void write(RecordType type, const std::vector<std::uint8_t>& payload) {
    std::lock_guard lock(mutex);
    writer->write(type, payload);
  }
};

SessionWriter::SessionWriter(const std::filesystem::path& file, const SessionSettings& settings, bool append)
    : impl_(std::make_unique<Impl>()) {
  std::error_code ec;
  const bool continuing = append && std::filesystem::exists(file, ec);
  if (continuing) load_session(file);  // refuse to append to a file that is not a session
  impl_->writer = std::make_unique<io::RecordingWriter>(file, continuing);
  if (!continuing) impl_->write(RecordType::settings, settings_payload(settings));
}

SessionWriter::~SessionWriter() = default;

void SessionWriter::chunk(const Chunk& c) { impl_->write(RecordType::chunk, chunk_payload(c)); }

void SessionWriter::pose(const RecordedPose& p) {
  io::BinaryWriter w;
  w.put<std::int64_t>(p.arrival_ns);
  const std::string line = pose_line(p.pose);
  w.put_array(line.data(), line.size());
  impl_->write(RecordType::pose, w.bytes());
}

void SessionWriter::reading(const FormedReading& f) { impl_->write(RecordType::reading, reading_payload(f)); }

void SessionWriter::note(const ContactNote& n) {
  io::BinaryWriter w;
  w.put<double>(n.time);
  w.put_array(n.text.data(), n.text.size());
  impl_->write(RecordType::note, w.bytes());
}

}  // namespace sva::drivers
