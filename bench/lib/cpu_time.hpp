#pragma once
// The bench programs' CPU clock (bench/speed/*.cpp).
#include <ctime>

namespace sva::bench {

// CPU seconds of the whole process (all threads): on a shared machine this is steadier than wall time; divided by the
// threads it bounds the wall time an idle machine would give.
inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace sva::bench
