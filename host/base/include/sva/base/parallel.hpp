#pragma once
// Deterministic parallel loops: work is split by index, every index writes only
// its own output, so results do not depend on the thread count.
#include <cstddef>
#include <functional>

namespace sva::util {

// Threads to use: SVA_THREADS if set, else hardware concurrency (at least 1).
unsigned default_threads();
// Runs fn(i) for i in [0, n) on up to `threads` threads (0 = default_threads()).
// Indices are handed out dynamically on oneTBB's persistent worker pool (a nested
// loop in its caller's arena, isolated); every item runs in sva's floating-point
// environment (float_environment.hpp). The first exception thrown is rethrown
// after the loop stops (the rest are cancelled). Checks for Ctrl-C between items.
void parallel_for(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads = 0);

// Runs fn(i) for i in [0, n) on up to `threads` workers (0 = default_threads()), dealt in index order from one shared
// counter: the caller orders the items (the largest first, so that the last to finish is a small one and no worker
// waits long for another; parallel_for's split by index ranges may give one worker all the large ones). Errors and
// Ctrl-C as parallel_for's: after the first error the other workers take no new item. Under a SpanProbe its items
// run in turn, each timed, as parallel_for's do.
void parallel_deal(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads = 0);

// The work and the span (critical path) of parallel code, measured on one thread: while a probe lives, this thread's
// parallel_for loops run their items in turn and time each, and the span counts, for each loop, only its longest item
// (an item's own span: its time less its nested loops', plus their spans). So span_ms is what unlimited cores could
// not beat, and a P-core run takes at least max(work / P, span) and, greedily scheduled, at most work / P + span
// (Brent), scheduling costs aside: a model of a many-core host from a machine with few. The loops decompose as for
// their `threads`, which the probe does not change. One probe per thread at a time.
// scheduled_ms is the model's point estimate between those bounds: each loop's items placed in the order they are
// handed out, each on the worker that frees first, of as many workers as the loop's `threads` (a dealt loop deals so;
// parallel_for's workers steal alike), a nested loop with every worker of its own. It leaves out what the bounds leave
// out, and the workers a nested loop shares with its outer loop's other items, so it is never below max(work / P,
// span) as printed (the bench programs take the larger).
class SpanProbe {
 public:
  SpanProbe();
  ~SpanProbe();
  SpanProbe(const SpanProbe&) = delete;
  SpanProbe& operator=(const SpanProbe&) = delete;
  double work_ms() const;  // since the probe began
  double span_ms() const;
  double scheduled_ms() const;

  struct Frame {  // an item's nested loops so far (internal)
    double nested_ms = 0.0, nested_span_ms = 0.0, nested_scheduled_ms = 0.0;
  };

 private:
  Frame root_;
  Frame* outer_;
  double start_ms_;
};

// The span of this thread's code between two laps, under a live SpanProbe (0 without one, or where the laps fall in
// different items of a probed loop): a stage's share of the probe's span, so that a model says which stage bounds it.
class SpanLap {
 public:
  SpanLap();
  double lap_ms();  // the span since construction or the last lap

 private:
  const SpanProbe::Frame* frame_ = nullptr;
  double at_ms_ = 0.0, nested_ms_ = 0.0, nested_span_ms_ = 0.0;
};

}  // namespace sva::util
