#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>
#include <vector>

#include <sva/base/float_environment.hpp>
#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/progress.hpp>

namespace sva::util {

namespace {
volatile std::sig_atomic_t g_interrupted = 0;
std::atomic<bool> g_quiet{false};
extern "C" void on_sigint(int) { g_interrupted = 1; }
}  // namespace

void install_interrupt_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
bool interrupted() { return g_interrupted != 0; }
void request_interrupt() { g_interrupted = 1; }
void clear_interrupt() { g_interrupted = 0; }

unsigned default_threads() {
  if (const char* env = std::getenv("SVA_THREADS")) {
    char* end = nullptr;
    long v = std::strtol(env, &end, 10);
    if (end && *end == '\0' && v >= 1 && v <= 1024) return static_cast<unsigned>(v);
  }
  unsigned hw = std::thread::hardware_concurrency();
  return hw ? hw : 1;
}

namespace {

thread_local SpanProbe::Frame* t_span = nullptr;  // the item a live probe is timing on this thread

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A loop under a probe: its items in turn, each timed in a frame of its own, and placed in their order on the one of
// `threads` workers that frees first (SpanProbe::scheduled_ms).
void probed_for(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads) {
  SpanProbe::Frame* outer = t_span;
  const StandardFloats floats;
  const double start = now_ms();
  double longest = 0.0;
  std::vector<double> free_at(std::min<std::size_t>(std::max(threads, 1u), n), 0.0);  // each worker's finish
  for (std::size_t i = 0; i < n; ++i) {
    throw_if_interrupted();
    SpanProbe::Frame item;
    t_span = &item;
    const double t = now_ms();
    try {
      fn(i);
    } catch (...) {
      t_span = outer;
      throw;
    }
    t_span = outer;
    const double own = now_ms() - t - item.nested_ms;
    longest = std::max(longest, own + item.nested_span_ms);
    *std::min_element(free_at.begin(), free_at.end()) += own + item.nested_scheduled_ms;
  }
  outer->nested_ms += now_ms() - start;
  outer->nested_span_ms += longest;
  outer->nested_scheduled_ms += *std::max_element(free_at.begin(), free_at.end());
}

}  // namespace

SpanProbe::SpanProbe() : outer_(t_span), start_ms_(now_ms()) { t_span = &root_; }
SpanProbe::~SpanProbe() { t_span = outer_; }
double SpanProbe::work_ms() const { return now_ms() - start_ms_; }
double SpanProbe::span_ms() const { return work_ms() - root_.nested_ms + root_.nested_span_ms; }
double SpanProbe::scheduled_ms() const { return work_ms() - root_.nested_ms + root_.nested_scheduled_ms; }

SpanLap::SpanLap() { lap_ms(); }
double SpanLap::lap_ms() {
  const double now = now_ms();
  const bool same = t_span && t_span == frame_;
  const double span =
      same ? now - at_ms_ - (t_span->nested_ms - nested_ms_) + (t_span->nested_span_ms - nested_span_ms_) : 0.0;
  frame_ = t_span;
  at_ms_ = now;
  nested_ms_ = t_span ? t_span->nested_ms : 0.0;
  nested_span_ms_ = t_span ? t_span->nested_span_ms : 0.0;
  return span;
}

// oneTBB's workers persist across calls (one pool per process), so the per-update loops of recognition pay no
// thread start-up. A loop runs in the caller's arena, isolated (a worker waiting at its end takes none of the caller's
// other tasks), where that arena has no more threads than asked: nested loops (an estimate's objects, then each
// object's starts) made an arena each before 2026-11-30, and a nested arena cost hundreds of microseconds to fill
// (notebook, recognition-2026-11.md). Otherwise an arena caps the threads at the caller's count. Every task runs in
// sva's floating-point environment (float_environment.hpp), whatever its thread or arena held.
void parallel_for(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads) {
  if (threads == 0) threads = default_threads();
  if (n == 0) return;
  if (t_span) return probed_for(n, fn, threads);
  const auto run = [&](std::size_t begin, std::size_t end) {
    const StandardFloats floats;
    for (std::size_t i = begin; i != end; ++i) {
      throw_if_interrupted();
      fn(i);
    }
  };
  if (threads <= 1 || n == 1) return run(0, n);
  // Grain 1: items (observed pairs, readings, chunks) are few and uneven.
  const auto loop = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) { run(r.begin(), r.end()); });
  };
  if (static_cast<unsigned>(tbb::this_task_arena::max_concurrency()) <= threads)
    return tbb::this_task_arena::isolate(loop);
  tbb::task_arena arena(static_cast<int>(std::min<std::size_t>(threads, n)));
  arena.execute(loop);
}

void parallel_deal(std::size_t n, const std::function<void(std::size_t)>& fn, unsigned threads) {
  if (threads == 0) threads = default_threads();
  if (t_span) return parallel_for(n, fn, threads);  // in order, each item timed and dealt on `threads` in the model
  if (threads <= 1 || n <= 1) return parallel_for(n, fn, 1);
  std::atomic<std::size_t> next{0};
  parallel_for(
      std::min<std::size_t>(threads, n),
      [&](std::size_t) {
        try {
          for (std::size_t k; (k = next.fetch_add(1)) < n;) {
            throw_if_interrupted();  // as parallel_for does between its items
            fn(k);
          }
        } catch (...) {
          next.store(n);  // the other workers stop after their current item
          throw;
        }
      },
      threads);
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_),
      tty_(::isatty(2) != 0) {}

Progress::~Progress() {
  if (!finished_ && tty_ && !g_quiet && done_ > 0) std::fputc('\n', stderr);
}

void Progress::set_quiet(bool quiet) { g_quiet = quiet; }

void Progress::advance(std::size_t n) {
  std::size_t done = done_.fetch_add(n) + n;
  if (g_quiet) return;
  auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (tty_) {
    if (now - last_draw_ < std::chrono::milliseconds(200) && done < total_) return;
    last_draw_ = now;
    draw(done, false);
  } else {
    int decile = total_ ? static_cast<int>(10 * done / total_) : 10;
    if (decile == last_decile_) return;
    last_decile_ = decile;
    draw(done, false);
  }
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (g_quiet) return;
  std::lock_guard lock(mutex_);
  if (!tty_ && last_decile_ == 10) return;  // the 100% line is already out
  draw(done_, true);
}

void Progress::draw(std::size_t done, bool final) {
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  double rate = secs > 0 ? static_cast<double>(done) / secs : 0.0;
  std::string eta;
  if (!final && rate > 0 && done < total_)
    eta = ", ~" + std::to_string(static_cast<int>((total_ - done) / rate + 0.5)) + " s left";
  std::fprintf(stderr, "%s%s: %zu/%zu (%.1f/s, %.1f s%s)%s", tty_ ? "\r\033[K" : "", label_.c_str(), done, total_, rate,
               secs, eta.c_str(), (tty_ && !final) ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace sva::util
