// The resynchronising byte-stream parser and the reader thread around it (drivers/src/frame.cpp FrameParser,
// drivers/src/sensor_stream.cpp). The input is split into transfers: each starts with a control byte whose low
// 7 bits give the transfer's length and whose top bit, with a zero length, is a link status change. The first
// byte picks the array size the stream expects (0: any).
#include <sva/drivers/frame.hpp>
#include <sva/drivers/sensor_stream.hpp>
#include <sva/error.hpp>

#include <cstdlib>
#include <memory>

namespace {

using namespace sva::drivers;

std::vector<Chunk> transfers(const std::uint8_t* data, std::size_t size) {
  std::vector<Chunk> chunks;
  std::int64_t t = 0;
  for (std::size_t at = 0; at < size;) {
    const std::uint8_t control = data[at++];
    t += 1000;
    const std::size_t n = control & 0x7f;
    if (n == 0 && (control & 0x80)) {
      const auto status = static_cast<LinkStatus>(1 + (at < size ? data[at++] % 3 : 0));  // idle, lost, back
      chunks.push_back({status, t, {}, "fuzz"});
      continue;
    }
    const std::size_t take = std::min(n, size - at);
    chunks.push_back({LinkStatus::data, t, std::vector<std::uint8_t>(data + at, data + at + take), {}});
    at += take;
  }
  return chunks;
}

void check(const StreamFrame& f, int rows, int cols) {
  if (f.frame.rows < 1 || f.frame.cols < 1 || (rows && f.frame.rows != rows) || (cols && f.frame.cols != cols) ||
      f.frame.counts.size() != static_cast<std::size_t>(f.frame.rows) * static_cast<std::size_t>(f.frame.cols))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int dim = data[0] % 4 == 0 ? 0 : data[0] % 4 == 1 ? 6 : data[0] % 4 == 2 ? 2 : 16;
  auto chunks = transfers(data + 1, size - 1);

  // The parser alone, transfer by transfer.
  FrameParser parser(dim, dim);
  std::uint64_t pushed = 0, framed = 0;
  for (const Chunk& c : chunks) {
    if (c.status != LinkStatus::data) {
      parser.reset();
      continue;
    }
    parser.push(c.bytes, c.host_ns);
    pushed += c.bytes.size();
    while (auto f = parser.next()) {
      check(*f, dim, dim);
      framed += frame_bytes(f->frame.rows, f->frame.cols);
    }
  }
  const ParserStats& s = parser.stats();
  if (s.bytes_in != pushed || framed + s.bytes_skipped + s.partial_dropped > pushed) std::abort();

  // The same transfers through the reader thread (a replay: it waits for the consumer, drops nothing).
  try {
    StreamOptions o;
    o.rows = o.cols = dim;
    o.block_when_full = true;
    o.ring_capacity = 64;
    SensorStream stream(std::make_unique<ReplayTransport>(std::move(chunks), 0.0, "fuzz"), o);
    std::uint64_t frames = 0;
    while (auto e = stream.next(std::chrono::seconds(10))) {
      if (e->status == LinkStatus::data) {
        check(e->frame, dim, dim);
        ++frames;
      }
      if (e->status == LinkStatus::ended || e->status == LinkStatus::failed) break;
    }
    if (frames != stream.stats().parser.frames) std::abort();
  } catch (const sva::Error&) {
  }
  return 0;
}
