#include <sva/io/recording_file.hpp>

#include <sva/error.hpp>

#include <cstring>
#include <fstream>

#include <sva/io/binary_file.hpp>

namespace sva::io {

namespace {
constexpr char kMagic[8] = {'S', 'V', 'A', 'R', 'E', 'C', '\r', '\n'};
constexpr std::size_t kFileHeader = 16, kRecordHeader = 8, kRecordTrailer = 8;
constexpr std::uint32_t kMaxPayload = 64u << 20;

std::uint64_t record_checksum(std::uint32_t type, std::uint32_t size, const std::uint8_t* payload) {
  std::vector<std::uint8_t> bytes(kRecordHeader + size);
  std::memcpy(bytes.data(), &type, 4);
  std::memcpy(bytes.data() + 4, &size, 4);
  if (size) std::memcpy(bytes.data() + kRecordHeader, payload, size);
  return fnv1a64(bytes.data(), bytes.size());
}

void put_bytes(std::FILE* f, const void* p, std::size_t n, const std::filesystem::path& file) {
  if (n && std::fwrite(p, 1, n, f) != n) throw Error(file.string() + ": write failed (disk full?)");
}
}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& file, bool append) : path_(file) {
  std::error_code ec;
  if (append && std::filesystem::exists(file, ec)) {
    auto contents = read_recording(file);  // validates the header
    std::filesystem::resize_file(file, contents.valid_bytes, ec);
    if (ec) throw Error(file.string() + ": cannot cut its incomplete last record: " + ec.message());
    file_ = std::fopen(file.c_str(), "ab");
    if (!file_) throw Error(file.string() + ": cannot open for appending");
    return;
  }
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw Error(file.string() + ": cannot create recording");
  const std::uint32_t version = kRecordingVersion, reserved = 0;
  put_bytes(file_, kMagic, 8, path_);
  put_bytes(file_, &version, 4, path_);
  put_bytes(file_, &reserved, 4, path_);
  std::fflush(file_);
}

RecordingWriter::~RecordingWriter() {
  if (file_) std::fclose(file_);
}

void RecordingWriter::write(RecordType type, const std::vector<std::uint8_t>& payload) {
  if (payload.size() > kMaxPayload)
    throw Error(path_.string() + ": record of " + std::to_string(payload.size()) +
                " bytes exceeds the format's 64 MiB limit");
  const auto t = static_cast<std::uint32_t>(type), n = static_cast<std::uint32_t>(payload.size());
  const std::uint64_t sum = record_checksum(t, n, payload.data());
  put_bytes(file_, &t, 4, path_);
  put_bytes(file_, &n, 4, path_);
  put_bytes(file_, payload.data(), payload.size(), path_);
  put_bytes(file_, &sum, 8, path_);
  if (std::fflush(file_) != 0) throw Error(path_.string() + ": write failed (disk full?)");
}

RecordingContents read_recording(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot read recording");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kFileHeader || std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw Error(file.string() + ": not an sva recording (bad magic)");
  RecordingContents out;
  std::memcpy(&out.version, bytes.data() + 8, 4);
  if (out.version < 1 || out.version > kRecordingVersion)
    throw Error(file.string() + ": recording version " + std::to_string(out.version) + " (this sva reads 1.." +
                std::to_string(kRecordingVersion) + ")");
  std::size_t at = kFileHeader;
  while (at < bytes.size()) {
    if (bytes.size() - at < kRecordHeader + kRecordTrailer) {
      out.tail_problem = "truncated record header at byte " + std::to_string(at);
      break;
    }
    std::uint32_t type, size;
    std::memcpy(&type, bytes.data() + at, 4);
    std::memcpy(&size, bytes.data() + at + 4, 4);
    if (size > kMaxPayload || bytes.size() - at - kRecordHeader - kRecordTrailer < size) {
      out.tail_problem = "truncated record at byte " + std::to_string(at);
      break;
    }
    const std::uint8_t* payload = bytes.data() + at + kRecordHeader;
    std::uint64_t sum;
    std::memcpy(&sum, payload + size, 8);
    if (sum != record_checksum(type, size, payload)) {
      out.tail_problem = "checksum mismatch in the record at byte " + std::to_string(at);
      break;
    }
    out.records.push_back({static_cast<RecordType>(type), std::vector<std::uint8_t>(payload, payload + size)});
    at += kRecordHeader + size + kRecordTrailer;
  }
  out.valid_bytes = at;
  return out;
}

}  // namespace sva::io
