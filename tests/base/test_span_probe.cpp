// util::SpanProbe (sva/base/parallel.hpp): the work and critical path of parallel loops, measured on one thread, the
// model estimate_speed gives of one session's latency on many cores. Each item's time is taken inside it as well, so
// the checks hold on a loaded machine: a preempted item is longer in both measures.
#include <catch2/catch.hpp>

#include <sva/base/parallel.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using sva::util::parallel_for;
using sva::util::SpanProbe;

namespace {

// Busy for `ms` of wall time; returns the time it took, as the item itself saw it.
double busy(double ms) {
  const auto t0 = std::chrono::steady_clock::now();
  double took = 0.0;
  while ((took = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()) < ms) {
  }
  return took;
}

constexpr double kSlack = 1.0;  // ms: the loop's own bookkeeping around the items

// An upper bound (a measure < the items' own times + kSlack) fails when the machine preempts the loop's bookkeeping
// between items, which no item sees; the CI's sanitizer stage on 2 loaded cores did. A probe that adds time of its own
// adds it on every try, so `trial(last)` runs until its upper bounds hold, at most 5 times, and CHECKs them on the
// last. Its lower bounds, which no preemption can break, it CHECKs on every try.
template <class Trial>
void until_within_slack(const Trial& trial) {
  for (int attempt = 1; attempt < 5; ++attempt)
    if (trial(false)) return;
  trial(true);
}

// A list schedule on 2 workers written out for the test: each item in order on the worker that frees first.
double two_worker_schedule(const std::vector<double>& items) {
  double a = 0.0, b = 0.0;
  for (const double t : items) (a <= b ? a : b) += t;
  return std::max(a, b);
}

}  // namespace

TEST_CASE("a span probe counts each loop's longest item, a nested loop by its own span, on the caller's thread") {
  until_within_slack([](bool last) {
    std::vector<double> top(2, 0.0), inner(3, 0.0);
    double serial = 0.0, between = 0.0;
    std::vector<std::thread::id> ran(5);
    const std::thread::id caller = std::this_thread::get_id();
    double work = 0.0, span = 0.0;
    {
      const SpanProbe probe;
      serial = busy(2.0);  // outside any loop: on the critical path, whole
      parallel_for(
          2,
          [&](std::size_t i) {
            ran[i] = std::this_thread::get_id();
            if (i == 0) {
              top[0] = busy(1.0);
              parallel_for(
                  3,
                  [&](std::size_t j) {
                    ran[2 + j] = std::this_thread::get_id();
                    inner[j] = busy(2.0 + j);
                  },
                  4);
            } else {
              top[1] = busy(3.0);
            }
          },
          4);
      between = busy(1.0);
      work = probe.work_ms();
      span = probe.span_ms();
    }
    for (const std::thread::id& id : ran) CHECK(id == caller);  // in turn, on the probe's thread, though 4 were asked
    // Item 0: 1 ms then a loop whose longest item is the third; item 1: 3 ms alone. The span takes the longer item.
    const double item0 = top[0] + inner[2], item1 = top[1];
    const double expected_span = serial + std::max(item0, item1) + between;
    const double expected_work = serial + top[0] + inner[0] + inner[1] + inner[2] + top[1] + between;
    INFO("work " << work << " ms (items " << expected_work << "), span " << span << " ms (items " << expected_span
                 << ")");
    CHECK(span >= expected_span);
    CHECK(work >= expected_work);
    CHECK(span < work - 4.0);  // the two short inner items and the shorter top item are off the path
    const bool within = span < expected_span + kSlack && work < expected_work + kSlack;
    if (!within && !last) return false;
    CHECK(span < expected_span + kSlack);
    CHECK(work < expected_work + kSlack);
    return within;
  });
}

TEST_CASE("a span probe lets an item's error through and measures nothing after it ends") {
  {
    const SpanProbe probe;
    CHECK_THROWS_AS(parallel_for(
                        3,
                        [](std::size_t i) {
                          if (i == 1) throw std::runtime_error("item 1");
                        },
                        2),
                    std::runtime_error);
    const double before = probe.span_ms();
    parallel_for(
        2, [](std::size_t) { busy(1.0); }, 2);  // the probe still counts after the error
    CHECK(probe.span_ms() >= before + 1.0);
  }
  // No probe: the loop runs on the pool as before, every item once.
  std::vector<int> hit(64, 0);
  parallel_for(
      64, [&](std::size_t i) { ++hit[i]; }, 2);
  CHECK(std::count(hit.begin(), hit.end(), 1) == 64);
}

TEST_CASE("a dealt loop runs every item once, in order under a probe, and lets the first error through") {
  using sva::util::parallel_deal;
  // On the workers: every item once, whatever the thread count.
  for (const unsigned threads : {1u, 2u, 16u}) {
    std::vector<int> hit(100, 0);
    parallel_deal(
        hit.size(), [&](std::size_t i) { ++hit[i]; }, threads);
    CHECK(std::count(hit.begin(), hit.end(), 1) == 100);
  }
  // Under a probe: in turn on the probe's thread, in the caller's order, the span its longest item.
  until_within_slack([](bool last) {
    std::vector<std::size_t> order;
    std::vector<std::thread::id> ran;
    std::vector<double> took(3, 0.0);
    double span = 0.0;
    {
      const SpanProbe probe;
      parallel_deal(
          3,
          [&](std::size_t i) {
            order.push_back(i);
            ran.push_back(std::this_thread::get_id());
            took[i] = busy(i == 1 ? 3.0 : 1.0);
          },
          8);
      span = probe.span_ms();
    }
    CHECK(order == std::vector<std::size_t>{0, 1, 2});
    for (const std::thread::id& id : ran) CHECK(id == std::this_thread::get_id());
    CHECK(span >= took[1]);
    if (span >= took[1] + kSlack && !last) return false;
    CHECK(span < took[1] + kSlack);
    return true;
  });
  // An item's error reaches the caller; the workers take no new item after it (some may finish theirs).
  std::atomic<int> started{0};
  CHECK_THROWS_AS(parallel_deal(
                      1000,
                      [&](std::size_t i) {
                        ++started;
                        if (i == 3) throw std::runtime_error("item 3");
                        busy(0.05);
                      },
                      2),
                  std::runtime_error);
  CHECK(started.load() < 1000);
}

TEST_CASE("span laps split a probe's span into its stages, and are 0 without a probe") {
  using sva::util::SpanLap;
  until_within_slack([](bool last) {
    double stage1 = 0.0, stage2 = 0.0, span = 0.0, longest = 0.0, between = 0.0, serial = 0.0;
    {
      const SpanProbe probe;
      SpanLap lap;
      // Stage 1: a loop of 3 items, its span the longest (4 ms) plus the 1 ms after it.
      std::vector<double> took(3, 0.0);
      parallel_for(
          3, [&](std::size_t i) { took[i] = busy(2.0 + static_cast<double>(i)); }, 4);
      between = busy(1.0);
      stage1 = lap.lap_ms();
      longest = *std::max_element(took.begin(), took.end());
      // Stage 2: serial, whole on the path.
      serial = busy(2.0);
      stage2 = lap.lap_ms();
      span = probe.span_ms();
    }
    CHECK(stage2 >= serial);
    CHECK(stage1 >= longest + between);
    CHECK(stage1 + stage2 <= span + 1e-9);
    const bool within =
        stage2 < serial + kSlack && stage1 < longest + between + kSlack && stage1 + stage2 > span - kSlack;
    if (!within && !last) return false;
    CHECK(stage2 < serial + kSlack);
    CHECK(stage1 < longest + between + kSlack);
    CHECK(stage1 + stage2 > span - kSlack);
    return within;
  });
  // Inside a probed loop's item the lap counts that item's own path; a lap begun in another item counts 0.
  until_within_slack([](bool last) {
    const SpanProbe probe;
    SpanLap outside;
    double inside = 0.0, took = 0.0, crossed = -1.0;
    parallel_for(
        2,
        [&](std::size_t i) {
          if (i == 0) {
            SpanLap lap;
            took = busy(1.0);
            inside = lap.lap_ms();
          } else {
            crossed = outside.lap_ms();  // begun outside the loop, read in an item: not one path
          }
        },
        2);
    // Against the time the item saw, not the 1 ms it asked for: a preempted item is longer in both measures.
    CHECK(inside >= took);
    CHECK(crossed == 0.0);
    if (inside >= took + kSlack && !last) return false;
    CHECK(inside < took + kSlack);
    return true;
  });
  SpanLap none;
  busy(0.5);
  CHECK(none.lap_ms() == 0.0);
}

TEST_CASE("a span probe's schedule places each loop's items in order on the worker that frees first") {
  using sva::util::parallel_deal;
  // 4 items of 3, 1, 1, 1 ms on 2 workers: 3 on one, the three short ones on the other, 3 ms; on 1 worker, 6 ms.
  const auto loop = [](unsigned threads, bool dealt, std::vector<double>* took) {
    took->assign(4, 0.0);
    const auto item = [&](std::size_t i) { (*took)[i] = busy(i == 0 ? 3.0 : 1.0); };
    if (dealt)
      parallel_deal(4, item, threads);
    else
      parallel_for(4, item, threads);
  };
  for (const bool dealt : {false, true}) {
    until_within_slack([&](bool last) {
      std::vector<double> took;
      double two = 0.0, one = 0.0, span = 0.0;
      {
        const SpanProbe probe;
        loop(2, dealt, &took);
        span = probe.span_ms();
        two = probe.scheduled_ms();  // read after the span: the time between the reads counts in both
      }
      // The expected schedule from the times the items saw: on a loaded machine a preempted short item can outlast the
      // long one, and the fourth item then goes to the long one's worker.
      const double expected = two_worker_schedule(took);
      INFO((dealt ? "dealt" : "parallel_for") << ": scheduled on 2 " << two << " ms, items " << took[0] << ", "
                                              << took[1] << ", " << took[2] << ", " << took[3] << " ms");
      CHECK(two >= expected);
      CHECK(two >= span);
      double work = 0.0;
      {
        const SpanProbe probe;
        loop(1, dealt, &took);
        one = probe.scheduled_ms();
        work = probe.work_ms();
      }
      CHECK(one >= took[0] + took[1] + took[2] + took[3]);
      const bool within = two < expected + kSlack && one >= work - kSlack;
      if (!within && !last) return false;
      CHECK(two < expected + kSlack);
      CHECK(one >= work - kSlack);  // one worker: the loop's whole work
      return within;
    });
  }
  // A nested loop counts by its own schedule: an item of 1 ms then 2 x 2 ms on 2 workers is 3 ms, beside an item of
  // 2 ms on the other worker.
  until_within_slack([](bool last) {
    double nested = 0.0, first = 0.0, inner = 0.0, second = 0.0;
    {
      const SpanProbe probe;
      parallel_for(
          2,
          [&](std::size_t i) {
            if (i == 1) {
              second = busy(2.0);
              return;
            }
            first = busy(1.0);
            std::vector<double> t(2, 0.0);
            parallel_for(
                2, [&](std::size_t j) { t[j] = busy(2.0); }, 2);
            inner = std::max(t[0], t[1]);
          },
          2);
      nested = probe.scheduled_ms();
    }
    CHECK(nested >= first + inner);
    if (nested >= std::max(first + inner, second) + kSlack && !last) return false;
    CHECK(nested < std::max(first + inner, second) + kSlack);
    return true;
  });
}
