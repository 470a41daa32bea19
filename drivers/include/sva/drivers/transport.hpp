#pragma once
// Where the sensor's bytes come from. A transport delivers the raw byte stream
// in chunks (one USB transfer, one recorded chunk) with the link's status; it
// knows nothing of frames. Implementations: UsbTransport (usb_transport.hpp)
// and ReplayTransport (below). A sensor with another firmware protocol is an
// adapter transport that turns its bytes into the frame format
// (docs/usb-sensor.md).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace sva::drivers {

enum class LinkStatus : std::uint8_t {
  data = 0,          // bytes arrived
  idle = 1,          // nothing within the timeout (the sensor paused)
  disconnected = 2,  // the device went away (cable pulled); the transport tries to reconnect
  reconnected = 3,   // it is back; its sequence numbers restart
  ended = 4,         // no more data ever (end of a recording, shutdown)
  failed = 5,        // an error that reconnecting cannot fix; `message` says which
};
const char* to_string(LinkStatus s);

// Host time on the monotonic clock, nanoseconds (frames and poses share it).
std::int64_t monotonic_ns();

struct Chunk {
  LinkStatus status = LinkStatus::data;
  std::int64_t host_ns = 0;  // when it arrived (monotonic_ns; a replay gives the recorded time)
  std::vector<std::uint8_t> bytes;
  std::string message;  // for status changes
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Waits up to `timeout` for the next chunk. After `ended` or `failed`, keeps
  // returning `ended`.
  virtual Chunk read(std::chrono::milliseconds timeout) = 0;
  // Makes a blocked read return soon (called from another thread).
  virtual void interrupt() {}
  virtual std::string describe() const = 0;
};

// Plays recorded chunks: at the recorded pace scaled by `speed` (2: twice as
// fast), or as fast as possible when speed is 0. Chunks keep their recorded
// times, so what is formed from them does not depend on the replay speed.
class ReplayTransport : public Transport {
 public:
  ReplayTransport(std::vector<Chunk> chunks, double speed, std::string name = "replay");
  Chunk read(std::chrono::milliseconds timeout) override;
  void interrupt() override;
  std::string describe() const override { return name_; }

 private:
  std::vector<Chunk> chunks_;
  std::size_t next_ = 0;
  double speed_;
  std::string name_;
  std::int64_t start_wall_ns_ = 0, start_recorded_ns_ = 0;
  std::atomic<bool> interrupted_{false};
};

}  // namespace sva::drivers
