#include <sva/drivers/transport.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

namespace sva::drivers {

const char* to_string(LinkStatus s) {
  switch (s) {
    case LinkStatus::data:
      return "data";
    case LinkStatus::idle:
      return "idle";
    case LinkStatus::disconnected:
      return "disconnected";
    case LinkStatus::reconnected:
      return "reconnected";
    case LinkStatus::ended:
      return "ended";
    case LinkStatus::failed:
      return "failed";
  }
  return "unknown";
}

std::int64_t monotonic_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

ReplayTransport::ReplayTransport(std::vector<Chunk> chunks, double speed, std::string name)
    : chunks_(std::move(chunks)), speed_(speed), name_(std::move(name)) {
  if (!(speed >= 0) || !std::isfinite(speed)) throw Error("replay speed must be 0 (maximum) or positive");
}

void ReplayTransport::interrupt() { interrupted_ = true; }

Chunk ReplayTransport::read(std::chrono::milliseconds timeout) {
  if (next_ >= chunks_.size() || interrupted_) return Chunk{LinkStatus::ended, 0, {}, "end of " + name_};
  const Chunk& c = chunks_[next_];
  if (speed_ > 0) {
    if (next_ == 0) {
      start_wall_ns_ = monotonic_ns();
      start_recorded_ns_ = c.host_ns;
    }
    // Wait for this chunk's recorded moment; a long recorded pause comes back as `idle` each timeout.
    const auto due =
        start_wall_ns_ + static_cast<std::int64_t>(static_cast<double>(c.host_ns - start_recorded_ns_) / speed_);
    const auto wait = due - monotonic_ns();
    const auto limit = std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
    if (wait > limit) {
      std::this_thread::sleep_for(std::chrono::nanoseconds(limit));
      return Chunk{LinkStatus::idle, monotonic_ns(), {}, {}};
    }
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
  }
  ++next_;
  return c;
}

}  // namespace sva::drivers
