// Replaying a recorded session through the live pipeline, and writing a
// simulated dataset as a recording (so every sensor path runs without hardware).
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>

#include <cmath>

namespace sva::drivers {

namespace {

void flush(ReadingFormer& former, const PipelineEvents& events, std::int64_t delivered_ns) {
  for (const auto& n : former.take_notes())
    if (events.on_note) events.on_note(n);
  for (const auto& r : former.take_readings())
    if (events.on_reading) events.on_reading(r, delivered_ns);
}

}  // namespace

StreamStats replay_session(const Session& session, double speed, const PipelineEvents& events) {
  const auto& calibration = session.settings.calibration;
  StreamOptions options;
  options.rows = calibration.sensor.rows;
  options.cols = calibration.sensor.cols;
  options.block_when_full = true;  // a recording can wait for the consumer
  SensorStream stream(std::make_unique<ReplayTransport>(session.chunks, speed, "recording"), options);
  ReadingFormer former(calibration, session.settings.settle);
  std::size_t next_pose = 0;
  // Poses join the frames in the order they arrived while recording, so a lagging pose stream lags again.
  auto poses_until = [&](std::int64_t ns) {
    while (next_pose < session.poses.size() && session.poses[next_pose].arrival_ns <= ns)
      former.add_pose(session.poses[next_pose++].pose);
  };
  for (;;) {
    auto e = stream.next(std::chrono::milliseconds(200));
    if (!e) {
      if (stream.finished()) break;
      continue;
    }
    const std::int64_t delivered = monotonic_ns();
    if (e->status == LinkStatus::data) {
      poses_until(e->host_ns);
      former.add_frame(e->frame);
    } else {
      if (events.on_link) events.on_link(*e);
      if (e->status == LinkStatus::disconnected) former.link_lost(static_cast<double>(e->host_ns) * 1e-9);
    }
    flush(former, events, delivered);
    if (e->status == LinkStatus::ended || e->status == LinkStatus::failed) break;
  }
  poses_until(INT64_MAX);
  former.poses_ended();
  flush(former, events, monotonic_ns());
  return stream.stats();
}

std::vector<TactileFrame> collect_frames(SensorStream& stream, int count, std::chrono::milliseconds timeout) {
  std::vector<TactileFrame> frames;
  while (static_cast<int>(frames.size()) < count) {
    auto e = stream.next(timeout);
    if (!e)
      throw Error(stream.describe() + ": no frame within " + std::to_string(timeout.count()) + " ms (" +
                  std::to_string(frames.size()) + " of " + std::to_string(count) + " collected)");
    if (e->status == LinkStatus::data)
      frames.push_back(std::move(e->frame.frame));
    else if (e->status != LinkStatus::reconnected)
      throw Error(stream.describe() + ": link " + to_string(e->status) + " after " + std::to_string(frames.size()) +
                  " of " + std::to_string(count) + " frames" + (e->message.empty() ? "" : " (" + e->message + ")"));
  }
  return frames;
}

Calibration export_calibration(const SensorSpec& sensor) { return Calibration::uniform(sensor, 0.01f, 1000.0f); }

void export_dataset_session(const Dataset& data, const Calibration& calibration, double touch_rate_hz,
                            double frame_rate_hz, const std::filesystem::path& out) {
  SessionSettings settings;
  settings.calibration = calibration;
  settings.settle.target_kpa = 0;  // the simulator's controller already converged: any contact is on target
  settings.settle.contact_kpa = 0.001;
  settings.settle.stable_kpa = 0.0;
  settings.device = "simulated dataset (sva export --recording)";
  const int held = settings.settle.frames + 1;
  if (!(touch_rate_hz > 0) || !(frame_rate_hz > 0) || frame_rate_hz / touch_rate_hz < held + 2)
    throw Error("export --recording: need at least " + std::to_string(held + 2) +
                " frames per touch (frame rate / touch rate)");
  const auto per_touch = static_cast<int>(std::floor(frame_rate_hz / touch_rate_hz));
  const auto frame_ns = static_cast<std::int64_t>(std::llround(1e9 / frame_rate_hz));
  SessionWriter writer(out, settings);
  TactileFrame frame{0, calibration.sensor.rows, calibration.sensor.cols, {}};
  const std::vector<float> unloaded(static_cast<std::size_t>(calibration.sensor.elements()), 0.0f);
  std::int64_t ns = 1'000'000'000;  // one second in: recordings start on an arbitrary clock
  for (const auto& sample : data.samples) {
    const Reading& r = sample.reading;
    if (r.status == ControllerStatus::no_contact) continue;
    if (r.pressure.size() != unloaded.size()) throw Error("export --recording: reading size differs from the sensor");
    for (int k = 0; k < per_touch; ++k, ns += frame_ns) {
      const bool pressing = k >= per_touch - held;
      if (k == per_touch - held || k == per_touch - 1) {
        PoseSample pose{static_cast<double>(ns) * 1e-9, r.position, r.normal, r.x_axis, r.status};
        writer.pose({ns, pose});
      }
      frame.counts = calibration.to_counts(pressing ? r.pressure : unloaded);
      writer.chunk(Chunk{LinkStatus::data, ns, encode_frame(frame), {}});
      ++frame.sequence;
    }
  }
  writer.chunk(Chunk{LinkStatus::ended, ns, {}, "end of export"});
}

}  // namespace sva::drivers
