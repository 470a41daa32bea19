#include <sva/drivers/frame.hpp>
#include <sva/error.hpp>

#include <array>
#include <string>

namespace sva::drivers {

namespace {
constexpr std::uint8_t kMagic0 = 'S', kMagic1 = 'T';
constexpr std::size_t kHeader = 6, kTrailer = 2;

std::uint16_t le16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
}  // namespace

std::size_t frame_bytes(int rows, int cols) {
  return kHeader + 2 * static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols) + kTrailer;
}

std::uint16_t crc16_ccitt(std::span<const std::uint8_t> bytes) {
  // Table-driven (one lookup per byte): the CRC is most of the parser's work on large arrays.
  static const auto table = [] {
    std::array<std::uint16_t, 256> t{};
    for (int b = 0; b < 256; ++b) {
      auto crc = static_cast<std::uint16_t>(b << 8);
      for (int i = 0; i < 8; ++i) crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
      t[static_cast<std::size_t>(b)] = crc;
    }
    return t;
  }();
  std::uint16_t crc = 0xffff;
  for (std::uint8_t b : bytes) crc = static_cast<std::uint16_t>((crc << 8) ^ table[((crc >> 8) ^ b) & 0xff]);
  return crc;
}

TactileFrame parse_frame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeader + kTrailer)
    throw Error("tactile frame: " + std::to_string(bytes.size()) + " bytes is shorter than a header");
  if (bytes[0] != kMagic0 || bytes[1] != kMagic1) throw Error("tactile frame: bad magic (expected 'ST')");
  TactileFrame f;
  f.rows = bytes[2];
  f.cols = bytes[3];
  f.sequence = le16(&bytes[4]);
  if (f.rows == 0 || f.cols == 0) throw Error("tactile frame: zero rows or columns");
  const std::size_t n = static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols);
  if (bytes.size() != frame_bytes(f.rows, f.cols))
    throw Error("tactile frame: " + std::to_string(bytes.size()) + " bytes, expected " +
                std::to_string(frame_bytes(f.rows, f.cols)) + " for " + std::to_string(f.rows) + " x " +
                std::to_string(f.cols));
  const std::size_t body = kHeader + 2 * n;
  if (crc16_ccitt(bytes.first(body)) != le16(&bytes[body]))
    throw Error("tactile frame: CRC mismatch (corrupted transfer)");
  f.counts.resize(n);
  for (std::size_t i = 0; i < n; ++i) f.counts[i] = le16(&bytes[kHeader + 2 * i]);
  return f;
}

std::vector<std::uint8_t> encode_frame(const TactileFrame& f) {
  if (f.rows < 1 || f.rows > 255 || f.cols < 1 || f.cols > 255 ||
      f.counts.size() != static_cast<std::size_t>(f.rows) * static_cast<std::size_t>(f.cols))
    throw Error("tactile frame: cannot encode " + std::to_string(f.rows) + " x " + std::to_string(f.cols) + " with " +
                std::to_string(f.counts.size()) + " counts");
  std::vector<std::uint8_t> out{kMagic0,
                                kMagic1,
                                static_cast<std::uint8_t>(f.rows),
                                static_cast<std::uint8_t>(f.cols),
                                static_cast<std::uint8_t>(f.sequence & 0xff),
                                static_cast<std::uint8_t>(f.sequence >> 8)};
  out.reserve(frame_bytes(f.rows, f.cols));
  for (auto c : f.counts) {
    out.push_back(static_cast<std::uint8_t>(c & 0xff));
    out.push_back(static_cast<std::uint8_t>(c >> 8));
  }
  auto crc = crc16_ccitt(out);
  out.push_back(static_cast<std::uint8_t>(crc & 0xff));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

FrameParser::FrameParser(int rows, int cols) : rows_(rows), cols_(cols) {}

void FrameParser::push(std::span<const std::uint8_t> bytes, std::int64_t host_ns) {
  // Compact only when the consumed prefix dominates, so the copy is amortised.
  if (begin_ > 0 && begin_ * 2 >= buffer_.size()) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(begin_));
    begin_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  stats_.bytes_in += bytes.size();
  last_ns_ = host_ns;
}

bool FrameParser::header_plausible(std::size_t at) const {
  const std::uint8_t* p = buffer_.data() + at;
  if (p[0] != kMagic0 || p[1] != kMagic1 || p[2] == 0 || p[3] == 0) return false;
  return (rows_ == 0 || p[2] == rows_) && (cols_ == 0 || p[3] == cols_);
}

void FrameParser::skip(std::size_t n) {
  begin_ += n;
  stats_.bytes_skipped += n;
}

std::uint32_t FrameParser::note_sequence(std::uint16_t sequence) {
  std::uint32_t missing = 0;
  if (last_sequence_) missing = static_cast<std::uint16_t>(sequence - *last_sequence_ - 1);
  if (missing) {
    ++stats_.sequence_gaps;
    stats_.frames_missing += missing;
  }
  last_sequence_ = sequence;
  return missing;
}

std::optional<StreamFrame> FrameParser::next() {
  for (;;) {
    const std::size_t available = buffer_.size() - begin_;
    if (available < kHeader) return std::nullopt;
    if (!header_plausible(begin_)) {
      skip(1);  // scan byte by byte for the next header
      continue;
    }
    const std::uint8_t* p = buffer_.data() + begin_;
    const std::size_t size = frame_bytes(p[2], p[3]);
    if (available < size) return std::nullopt;  // the rest of the frame is in a later transfer
    const std::size_t body = size - kTrailer;
    if (crc16_ccitt(std::span(p, body)) != le16(p + body)) {
      // A corrupted frame, or a false header inside data: step past its magic and rescan, so that a valid
      // frame starting inside these bytes is still found.
      ++stats_.crc_errors;
      skip(1);
      continue;
    }
    StreamFrame out;
    out.frame.rows = p[2];
    out.frame.cols = p[3];
    out.frame.sequence = le16(p + 4);
    out.frame.counts.resize((body - kHeader) / 2);
    for (std::size_t i = 0; i < out.frame.counts.size(); ++i) out.frame.counts[i] = le16(p + kHeader + 2 * i);
    out.host_ns = last_ns_;
    out.missing_before = note_sequence(out.frame.sequence);
    begin_ += size;
    ++stats_.frames;
    return out;
  }
}

void FrameParser::reset() {
  stats_.partial_dropped += buffer_.size() - begin_;
  buffer_.clear();
  begin_ = 0;
  last_sequence_.reset();
}

}  // namespace sva::drivers
