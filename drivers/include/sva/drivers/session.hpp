#pragma once
// A recorded sensor session: what `sva record` writes and `sva replay` plays
// (docs/recording-format.md). The raw chunks are kept as they arrived, so a
// replay goes through the same parser, settle rule and pose matching as the
// live run; poses keep their arrival time, so a lagging pose stream lags the
// same way again.
#include <sva/dataset.hpp>
#include <sva/drivers/calibration.hpp>
#include <sva/drivers/contact_readings.hpp>
#include <sva/drivers/sensor_stream.hpp>
#include <sva/drivers/transport.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sva::drivers {

struct SessionSettings {
  Calibration calibration;
  SettleRule settle;
  std::string device;  // what recorded it ("USB serial A12", "export of FILE")
};

struct RecordedPose {
  std::int64_t arrival_ns = 0;  // when the line arrived (host monotonic clock)
  PoseSample pose;
};

struct Session {
  SessionSettings settings;
  std::vector<Chunk> chunks;  // raw bytes and link status changes, in arrival order
  std::vector<RecordedPose> poses;
  std::vector<FormedReading> readings;  // formed while recording
  std::vector<ContactNote> notes;
  std::string tail_problem;  // "" or why the file ends early (crash, pulled cable): everything before it is kept
};

// Throws sva::Error naming the file when it is not a readable recording or has
// no settings record.
Session load_session(const std::filesystem::path& file);

class SessionWriter {
 public:
  // Starts a recording with its settings (or appends to one, keeping its settings).
  SessionWriter(const std::filesystem::path& file, const SessionSettings& settings, bool append = false);
  ~SessionWriter();
  // Thread-safe: the reader thread writes chunks while the main thread writes poses.
  void chunk(const Chunk& chunk);
  void pose(const RecordedPose& pose);
  void reading(const FormedReading& reading);
  void note(const ContactNote& note);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The live and replay pipeline after the transport: frames from the stream,
// poses by arrival, readings out. `on_reading` is called as each reading forms,
// with the host time its last frame was delivered to the consumer (latency).
struct PipelineEvents {
  std::function<void(const FormedReading&, std::int64_t delivered_ns)> on_reading;
  std::function<void(const ContactNote&)> on_note;
  std::function<void(const SensorEvent&)> on_link;  // status changes (disconnected, reconnected, ...)
};

// Replays a session: its chunks through a ReplayTransport (speed 0: as fast as
// possible) and a SensorStream, its poses by arrival time. Returns the stream's
// statistics.
StreamStats replay_session(const Session& session, double speed, const PipelineEvents& events);

// The arm's pose stream as it arrives: JSON lines from a file, a named pipe or
// stdin ("-"), read on a thread of its own (a pipe blocks) and stamped with
// their arrival time.
class PoseStream {
 public:
  explicit PoseStream(const std::string& source);  // throws when the file cannot be opened
  // Poses that arrived since the last call, lines that could not be read (with
  // FILE:LINE and the fault), and whether the stream has ended.
  void take(std::vector<RecordedPose>& poses, std::vector<std::string>& problems, bool& ended);

  struct State;

 private:
  std::shared_ptr<State> state_;
};

// Records live: frames from `transport`, poses from `poses`, readings formed as
// contacts settle; everything is written to `writer` (when given) as it
// happens. Runs until `keep_going()` says no, the link ends or fails.
struct LiveOptions {
  SessionSettings settings;
  SessionWriter* writer = nullptr;
  std::function<bool()> keep_going = [] { return true; };
};
StreamStats run_live(std::unique_ptr<Transport> transport, PoseStream& poses, const LiveOptions& options,
                     const PipelineEvents& events);

// The first `count` frames of a stream (the array unloaded), for Calibration::tare. Throws when the link
// ends or fails first, or when no frame arrives within `timeout` (naming the stream).
std::vector<TactileFrame> collect_frames(SensorStream& stream, int count, std::chrono::milliseconds timeout);

// A simulated dataset as a recording: each sample with contact becomes a touch
// at `touch_rate_hz` (unloaded frames, then the pressure image held for the
// settle window plus one), frames at `frame_rate_hz` encoded with `calibration`,
// and the sensor pose held during the touch (with the sample's controller status).
void export_dataset_session(const Dataset& data, const Calibration& calibration, double touch_rate_hz,
                            double frame_rate_hz, const std::filesystem::path& out);
// The calibration export uses for a dataset: 0.01 kPa per count, zero at 1000
// counts (the quantisation error is at most 0.005 kPa).
Calibration export_calibration(const SensorSpec& sensor);

}  // namespace sva::drivers
