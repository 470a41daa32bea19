#include <sva/drivers/sensor_stream.hpp>

namespace sva::drivers {

SensorStream::SensorStream(std::unique_ptr<Transport> transport, StreamOptions options)
    : transport_(std::move(transport)),
      options_(std::move(options)),
      parser_(options_.rows, options_.cols),
      ring_(options_.ring_capacity) {
  thread_ = std::thread([this] { run(); });
}

SensorStream::~SensorStream() { stop(); }

void SensorStream::stop() {
  stop_ = true;
  transport_->interrupt();
  ring_.close();
  if (thread_.joinable()) thread_.join();
}

void SensorStream::run() {
  for (;;) {
    Chunk chunk =
        stop_ ? Chunk{LinkStatus::ended, monotonic_ns(), {}, "stopped"} : transport_->read(options_.read_timeout);
    if (options_.on_chunk && chunk.status != LinkStatus::idle) options_.on_chunk(chunk);
    handle(chunk);
    if (chunk.status == LinkStatus::ended || chunk.status == LinkStatus::failed) break;
  }
  ring_.close();
}

void SensorStream::handle(Chunk& chunk) {
  if (chunk.status == LinkStatus::data) {
    parser_.push(chunk.bytes, chunk.host_ns);
    while (auto frame = parser_.next()) {
      SensorEvent e{LinkStatus::data, std::move(*frame), chunk.host_ns, {}};
      if (options_.block_when_full)
        ring_.push_wait(std::move(e));
      else
        ring_.try_push(std::move(e));
    }
    std::lock_guard lock(stats_mutex_);
    stats_.parser = parser_.stats();
    return;
  }
  {
    std::lock_guard lock(stats_mutex_);
    if (chunk.status == LinkStatus::idle) {
      ++stats_.idle_timeouts;
      return;  // a pause is visible in the frames' times; not queued
    }
    if (chunk.status == LinkStatus::disconnected) ++stats_.disconnects;
    if (chunk.status == LinkStatus::reconnected) ++stats_.reconnects;
  }
  // A partial frame cannot be completed by a device that went away or restarted.
  if (chunk.status != LinkStatus::ended) parser_.reset();
  {
    std::lock_guard lock(stats_mutex_);
    stats_.parser = parser_.stats();
  }
  ring_.push_wait(SensorEvent{chunk.status, {}, chunk.host_ns, chunk.message});
}

std::optional<SensorEvent> SensorStream::next(std::chrono::nanoseconds timeout) { return ring_.pop(timeout); }

StreamStats SensorStream::stats() const {
  std::lock_guard lock(stats_mutex_);
  StreamStats s = stats_;
  s.ring_overflows = ring_.overflows();
  return s;
}

}  // namespace sva::drivers
