#pragma once
// A running sensor: a reader thread pulls chunks from a transport, finds frames
// with the resynchronising parser and queues them, with every change of link
// status, in a bounded ring buffer for the consumer. Stopping (or destroying)
// the stream interrupts the transport and joins the thread.
#include <sva/drivers/frame.hpp>
#include <sva/drivers/ring_buffer.hpp>
#include <sva/drivers/transport.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace sva::drivers {

struct SensorEvent {
  LinkStatus status = LinkStatus::data;  // data: `frame` holds a frame; else a link status change
  StreamFrame frame;
  std::int64_t host_ns = 0;
  std::string message;
};

struct StreamStats {
  ParserStats parser;
  std::uint64_t ring_overflows = 0;  // frames the consumer was too slow to take
  std::uint64_t disconnects = 0, reconnects = 0, idle_timeouts = 0;
};

struct StreamOptions {
  int rows = 0, cols = 0;            // the array's size (0: any)
  std::size_t ring_capacity = 4096;  // frames (4 s of a 1 kHz sensor)
  std::chrono::milliseconds read_timeout{100};
  // Replay: wait for the consumer instead of dropping frames (a live sensor cannot wait; a recording can).
  bool block_when_full = false;
  // Called on the reader thread with every chunk as it arrives (recording raw bytes).
  std::function<void(const Chunk&)> on_chunk;
};

class SensorStream {
 public:
  SensorStream(std::unique_ptr<Transport> transport, StreamOptions options);
  ~SensorStream();
  SensorStream(const SensorStream&) = delete;
  SensorStream& operator=(const SensorStream&) = delete;

  // The next frame or status change; nothing after `timeout`. After the
  // `ended` or `failed` event, always nothing.
  std::optional<SensorEvent> next(std::chrono::nanoseconds timeout);
  bool finished() const { return ring_.closed_and_empty(); }
  void stop();
  StreamStats stats() const;
  std::string describe() const { return transport_->describe(); }

 private:
  void run();
  void handle(Chunk& chunk);
  std::unique_ptr<Transport> transport_;
  StreamOptions options_;
  FrameParser parser_;
  RingBuffer<SensorEvent> ring_;
  mutable std::mutex stats_mutex_;
  StreamStats stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace sva::drivers
