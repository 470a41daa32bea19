// Throughput of the sensor's byte path on one core: the resynchronising parser
// and the ring buffer, fed 4 KiB transfers of a recorded-like stream. Prints
// frames per second (goal: >= 100x a 1 kHz sensor) for two array sizes, and the
// same through a SensorStream (reader thread + consumer, replay at full speed).
#include <sva/drivers/frame.hpp>
#include <sva/drivers/ring_buffer.hpp>
#include <sva/drivers/sensor_stream.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>

using namespace sva::drivers;

namespace {

std::vector<std::uint8_t> make_stream(int rows, int cols, int frames) {
  std::vector<std::uint8_t> stream;
  TactileFrame f{0, rows, cols, std::vector<std::uint16_t>(static_cast<std::size_t>(rows * cols))};
  for (int k = 0; k < frames; ++k) {
    f.sequence = static_cast<std::uint16_t>(k);
    for (std::size_t i = 0; i < f.counts.size(); ++i) f.counts[i] = static_cast<std::uint16_t>(1000 + i + k);
    auto b = encode_frame(f);
    stream.insert(stream.end(), b.begin(), b.end());
  }
  return stream;
}

// CPU time of this thread: on a shared machine the wall clock also counts other programs' turns.
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void one_core(int rows, int cols, int frames) {
  const auto stream = make_stream(rows, cols, frames);
  FrameParser parser(rows, cols);
  RingBuffer<StreamFrame> ring(4096);
  std::size_t got = 0;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  for (std::size_t at = 0; at < stream.size(); at += 4096) {
    parser.push(std::span(stream).subspan(at, std::min<std::size_t>(4096, stream.size() - at)), 0);
    while (auto f = parser.next()) ring.try_push(std::move(*f));
    while (ring.pop(std::chrono::nanoseconds(0))) ++got;
  }
  const double s = seconds_since(start), cpu = thread_cpu_seconds() - cpu_start;
  std::printf(
      "parser + ring, one core, %dx%d array: %zu frames in %.3f s CPU (%.3f s wall) = %.0f frames per CPU second "
      "(%.0fx a 1 kHz sensor)\n",
      rows, cols, got, cpu, s, static_cast<double>(got) / cpu, static_cast<double>(got) / cpu / 1000.0);
}

void threaded(int rows, int cols, int frames) {
  const auto stream = make_stream(rows, cols, frames);
  std::vector<Chunk> chunks;
  for (std::size_t at = 0; at < stream.size(); at += 4096)
    chunks.push_back(
        {LinkStatus::data,
         0,
         std::vector<std::uint8_t>(stream.begin() + static_cast<std::ptrdiff_t>(at),
                                   stream.begin() + static_cast<std::ptrdiff_t>(std::min(at + 4096, stream.size()))),
         {}});
  StreamOptions o;
  o.rows = rows;
  o.cols = cols;
  o.block_when_full = true;
  const auto start = std::chrono::steady_clock::now();
  SensorStream s(std::make_unique<ReplayTransport>(std::move(chunks), 0.0), o);
  std::size_t got = 0;
  while (auto e = s.next(std::chrono::seconds(5)))
    if (e->status == LinkStatus::data) ++got;
  const double t = seconds_since(start);
  std::printf("SensorStream (reader thread + consumer), %dx%d array: %zu frames in %.3f s = %.0f frames/s\n", rows,
              cols, got, t, static_cast<double>(got) / t);
}

}  // namespace

int main() {
  one_core(6, 6, 1'000'000);
  one_core(16, 16, 200'000);
  threaded(6, 6, 1'000'000);
  return 0;
}
