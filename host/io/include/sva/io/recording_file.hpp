#pragma once
// A sensor session recording (.svar): an append-only sequence of checksummed
// records, so that a crash or a pulled cable leaves a file that is valid up to
// its last complete record. Layout (little-endian), docs/recording-format.md:
//   header: magic "SVAREC\r\n" | u32 version | u32 reserved
//   record: u32 type | u32 payload_bytes | payload | u64 fnv1a64(type, payload_bytes, payload)
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace sva::io {

enum class RecordType : std::uint32_t {
  settings = 1,  // JSON text: {"calibration": {...}, "settle": {...}, "device": "..."}
  chunk = 2,     // i64 host_ns | u8 link status | u32 message bytes | message | raw bytes (rest)
  pose = 3,      // one pose JSON line (drivers::pose_line)
  reading = 4,   // f64 time | u16 sequence | 9 f64 pose | u8 status | u16 iterations | u32 n | n f32 kPa
  note = 5,      // f64 time | text
};

struct Record {
  RecordType type;
  std::vector<std::uint8_t> payload;
};

inline constexpr std::uint32_t kRecordingVersion = 1;

class RecordingWriter {
 public:
  // Creates the file, or with `append` continues an existing recording (after
  // cutting an incomplete last record left by a crash).
  RecordingWriter(const std::filesystem::path& file, bool append);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;
  // Writes and flushes one record (a crash after this keeps it).
  void write(RecordType type, const std::vector<std::uint8_t>& payload);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

struct RecordingContents {
  std::uint32_t version = 0;
  std::vector<Record> records;    // every complete record, in order (unknown types included)
  std::uint64_t valid_bytes = 0;  // the file is valid up to here
  std::string tail_problem;       // "" or why reading stopped early (truncated or corrupted last record)
};

// Reads every complete record; throws sva::Error naming the file when it is not
// a recording at all (missing, bad magic, newer version).
RecordingContents read_recording(const std::filesystem::path& file);

}  // namespace sva::io
