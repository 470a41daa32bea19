#pragma once
// Deterministic parallel loops: work is split by index, every index writes only
// its own output, so results do not depend on the thread count.
#include <cstddef>
#include <functional>

namespace sva::util {

// Threads to use: SVA_THREADS if set, else hardware concurrency (at least 1).
unsigned default_threads();
// Runs fn(i) for i in [0, n) on up to `threads` threads (0 = default_threads()).
// Indices are handed out dynamically on oneTBB's persistent worker pool; the
// first exception thrown is rethrown after the loop stops (the rest are
// cancelled). Checks for Ctrl-C between items.
void parallel_for(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads = 0);

}  // namespace sva::util
