#pragma once
// The tactile array's wire format and the resynchronising parser that finds
// frames in a raw byte stream. USB bulk transfers do not respect frame
// boundaries: a transfer may hold half a frame, several frames, or bytes
// corrupted on the way; the parser turns whatever arrives into complete,
// checksummed frames and counts everything it had to skip. Format:
// docs/usb-sensor.md.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace sva::drivers {

struct TactileFrame {
  std::uint16_t sequence = 0;
  int rows = 0, cols = 0;
  std::vector<std::uint16_t> counts;  // row-major raw ADC counts
};

// Parses exactly one frame; throws sva::Error describing the fault (bad magic,
// size, CRC).
TactileFrame parse_frame(std::span<const std::uint8_t> bytes);
// The frame encoder (for tests, emulators and `sva export --recording`).
std::vector<std::uint8_t> encode_frame(const TactileFrame& frame);
std::uint16_t crc16_ccitt(std::span<const std::uint8_t> bytes);
// Header (magic, rows, cols, sequence) + counts + CRC.
std::size_t frame_bytes(int rows, int cols);

// A frame found in the stream, stamped with the host time (monotonic clock,
// nanoseconds) of the transfer that completed it.
struct StreamFrame {
  TactileFrame frame;
  std::int64_t host_ns = 0;
  std::uint32_t missing_before = 0;  // frames the sequence numbers say were lost just before this one
};

struct ParserStats {
  std::uint64_t bytes_in = 0;
  std::uint64_t frames = 0;
  std::uint64_t bytes_skipped = 0;    // bytes that were not part of any valid frame (noise, corrupted frames)
  std::uint64_t crc_errors = 0;       // candidate frames (valid header) whose CRC failed
  std::uint64_t sequence_gaps = 0;    // places where sequence numbers jumped
  std::uint64_t frames_missing = 0;   // frames lost in those jumps
  std::uint64_t partial_dropped = 0;  // bytes of an incomplete frame discarded by reset() (link lost mid-frame)
};

class FrameParser {
 public:
  // rows/cols: the array's size; headers announcing another size are noise
  // (this rejects false headers at once instead of waiting for a huge frame).
  // 0: any size.
  explicit FrameParser(int rows = 0, int cols = 0);
  // Appends the bytes of one transfer received at host_ns.
  void push(std::span<const std::uint8_t> bytes, std::int64_t host_ns);
  // The next complete valid frame, or nothing until more bytes arrive. Drain
  // after every push so that frames carry their own transfer's time.
  std::optional<StreamFrame> next();
  // After a disconnect: drops a partial frame and forgets the last sequence
  // number (a re-plugged device restarts its count).
  void reset();
  const ParserStats& stats() const { return stats_; }

 private:
  bool header_plausible(std::size_t at) const;
  void skip(std::size_t n);
  std::uint32_t note_sequence(std::uint16_t sequence);
  int rows_, cols_;
  std::vector<std::uint8_t> buffer_;
  std::size_t begin_ = 0;
  std::int64_t last_ns_ = 0;
  std::optional<std::uint16_t> last_sequence_;
  ParserStats stats_;
};

}  // namespace sva::drivers
