#include "roofline/host_reads.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

namespace sva::bench {

namespace {

// The sum of `n` words read through a volatile pointer (each a load the compiler may not merge or drop), and the
// best time of three passes in nanoseconds per load.
double sum_words(const vk::Buffer& b, std::size_t n, std::uint64_t* sum) {
  const volatile std::uint64_t* w = b.as<std::uint64_t>();
  double best = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    std::uint64_t s = 0;
    for (std::size_t i = 0; i < n; ++i) s += w[i];
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, ns / static_cast<double>(n));
    *sum = s;
  }
  return best;
}

}  // namespace

HostReads measure_host_reads(vk::Context& ctx, std::size_t loads) {
  const std::size_t bytes = loads * sizeof(std::uint64_t);
  vk::Buffer mapped = ctx.create_buffer(bytes);
  vk::Buffer copy = ctx.create_readback_buffer(bytes);
  // The device writes the words (a fill, as a kernel's result would land) and copies them in the same submission.
  constexpr std::uint32_t kWord = 0x01020304u;
  ctx.run({}, nullptr, {{&mapped, kWord, 0, bytes}}, {{&mapped, &copy, 0, 0, bytes}});
  HostReads r;
  r.loads = loads;
  r.mapped_device_local = mapped.device_local();
  std::uint64_t in_place = 0, copied = 0;
  r.mapped_ns_per_load = sum_words(mapped, loads, &in_place);
  r.readback_ns_per_load = sum_words(copy, loads, &copied);
  const std::uint64_t want = static_cast<std::uint64_t>(loads) * (std::uint64_t{kWord} << 32 | kWord);
  r.sums_agree = in_place == want && copied == want;
  return r;
}

}  // namespace sva::bench
