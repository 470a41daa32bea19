#pragma once
// Host memory of the benchmark process as Linux reports it (/proc/self/status,
// getrusage): what a backend's run costs in RAM, next to the time and accuracy
// it buys (`sva bench`, bench/speed/filter_speed).
#include <cstdint>
#include <optional>

namespace sva::bench {

// The resident set now and its high-water mark (VmRSS, VmHWM) in bytes; 0 where
// /proc/self/status cannot be read (not Linux).
struct ResidentMemory {
  std::uint64_t rss_bytes = 0;
  std::uint64_t hwm_bytes = 0;
};
ResidentMemory resident_memory();

// getrusage's ru_maxrss in bytes. On Linux, resetting VmHWM lowers it too.
std::uint64_t max_rss_bytes();

// Host memory of one run.
struct RunMemory {
  std::uint64_t rss_before_bytes = 0;  // VmRSS when the run started
  std::uint64_t rss_after_bytes = 0;   // VmRSS at its end, while its backend still holds its memory
  // The highest resident set during the run (VmHWM reset at its start); none where the reset failed.
  std::optional<std::uint64_t> peak_during_bytes;
  std::uint64_t process_peak_bytes = 0;  // the process's highest resident set so far, the run included
  std::int64_t rss_increase_bytes() const {
    return static_cast<std::int64_t>(rss_after_bytes) - static_cast<std::int64_t>(rss_before_bytes);
  }
};

// Measures runs one after another in one process. The peak during a run needs
// VmHWM reset at its start (writing "5" to /proc/self/clear_refs); that also
// lowers ru_maxrss, so the meter keeps the process peak itself: the most it
// has read so far. Where the reset fails (not Linux, an old kernel, a sandbox)
// runs report no peak of their own and the process peak still holds. Linux
// counts RSS per CPU and sums it lazily, so readings are good to a few hundred
// KiB; the meter keeps its own figures consistent (a run's peak is at least its
// final RSS and at most the process peak).
class MemoryMeter {
 public:
  void start();
  RunMemory stop();
  // The highest resident set of the process so far.
  std::uint64_t process_peak_bytes();

 private:
  std::uint64_t peak_seen_ = 0;
  std::uint64_t rss_before_ = 0;
  bool peak_reset_ = false;
};

}  // namespace sva::bench
