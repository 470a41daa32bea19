// The live pipeline: a sensor stream and the arm's pose stream into readings,
// everything recorded as it happens (sva record).
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>

#include <deque>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

namespace sva::drivers {

struct PoseStream::State {
  std::mutex mutex;
  std::deque<RecordedPose> poses;
  std::vector<std::string> problems;
  bool ended = false;
  std::string source;
  std::ifstream file;
};

namespace {

void read_poses(PoseStream::State& state) {
  std::istream& in = state.source == "-" ? std::cin : state.file;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto arrival = monotonic_ns();
    std::lock_guard lock(state.mutex);
    try {
      state.poses.push_back({arrival, parse_pose_line(line, state.source + ":" + std::to_string(n))});
    } catch (const Error& e) {
      state.problems.push_back(e.what());
    }
  }
  std::lock_guard lock(state.mutex);
  state.ended = true;
}

// One pass: poses that arrived, then at most one sensor event. False when the link has ended.
struct LiveStep {
  const LiveOptions& options;
  const PipelineEvents& events;
  ReadingFormer former;
  bool told_poses_ended = false;
  std::vector<RecordedPose> arrived;
  std::vector<std::string> problems;

  void take_poses(PoseStream& poses) {
    bool ended = false;
    poses.take(arrived, problems, ended);
    for (const auto& p : arrived) {
      if (options.writer) options.writer->pose(p);
      former.add_pose(p.pose);
    }
    for (const auto& text : problems) note({static_cast<double>(monotonic_ns()) * 1e-9, text + " (skipped)"});
    if (ended && !told_poses_ended) {
      former.poses_ended();  // contacts waiting for a pose are dropped with a note; frames are still recorded
      told_poses_ended = true;
    }
  }
  void note(const ContactNote& n) {
    if (options.writer) options.writer->note(n);
    if (events.on_note) events.on_note(n);
  }
  void emit() {
    for (const auto& n : former.take_notes()) note(n);
    for (const auto& r : former.take_readings()) {
      if (options.writer) options.writer->reading(r);
      if (events.on_reading) events.on_reading(r, monotonic_ns());
    }
  }
  bool sensor(SensorStream& stream) {
    auto e = stream.next(std::chrono::milliseconds(50));
    const std::int64_t delivered = monotonic_ns();
    if (e && e->status == LinkStatus::data) former.add_frame(e->frame);
    if (e && e->status != LinkStatus::data) {
      if (events.on_link) events.on_link(*e);
      if (e->status == LinkStatus::disconnected) former.link_lost(static_cast<double>(e->host_ns) * 1e-9);
    }
    for (const auto& n : former.take_notes()) note(n);
    for (const auto& r : former.take_readings()) {
      if (options.writer) options.writer->reading(r);
      if (events.on_reading) events.on_reading(r, delivered);
    }
    return !(e && (e->status == LinkStatus::failed || e->status == LinkStatus::ended)) && !stream.finished();
  }
};

}  // namespace

PoseStream::PoseStream(const std::string& source) : state_(std::make_shared<State>()) {
  state_->source = source;
  if (source != "-") {
    state_->file.open(source);
    if (!state_->file) throw Error(source + ": cannot read the pose stream");
  }
  // A blocked read of stdin cannot be cancelled: the thread owns the state it uses and the process ends it.
  std::thread([state = state_] { read_poses(*state); }).detach();
}

void PoseStream::take(std::vector<RecordedPose>& poses, std::vector<std::string>& problems, bool& ended) {
  std::lock_guard lock(state_->mutex);
  poses.assign(state_->poses.begin(), state_->poses.end());
  state_->poses.clear();
  problems = std::move(state_->problems);
  state_->problems.clear();
  ended = state_->ended;
}

StreamStats run_live(std::unique_ptr<Transport> transport, PoseStream& poses, const LiveOptions& options,
                     const PipelineEvents& events) {
  StreamOptions stream_options;
  stream_options.rows = options.settings.calibration.sensor.rows;
  stream_options.cols = options.settings.calibration.sensor.cols;
  if (options.writer) stream_options.on_chunk = [w = options.writer](const Chunk& c) { w->chunk(c); };
  SensorStream stream(std::move(transport), stream_options);
  LiveStep step{options, events, ReadingFormer(options.settings.calibration, options.settings.settle)};
  for (;;) {
    step.take_poses(poses);
    if (!options.keep_going() || !step.sensor(stream)) break;
  }
  stream.stop();
  step.take_poses(poses);  // poses that arrived with the last frames
  step.emit();
  return stream.stats();
}

}  // namespace sva::drivers
