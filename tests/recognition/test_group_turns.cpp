// Groups in flight on several workers (group_turns.hpp): the turns keep group order, and a failing batch reports its
// first failing group's error, whatever the timing.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "recognition/group_turns.hpp"

using namespace sva;

namespace {

// Group g on its worker: fetch in turn, some work (longer for some groups, so that workers overtake each other),
// done in turn; each stage's order recorded.
struct Recorded {
  std::mutex mutex;
  std::vector<std::size_t> fetched, done, worker_of;
};

void run_group(batch::GroupTurns& turns, Recorded& r, std::size_t g, std::size_t w, std::size_t fail_at = 1000,
               std::size_t fail_slow = 1000) {
  turns.wait(batch::GroupTurns::kFetch, g);
  {
    std::lock_guard lock(r.mutex);
    r.fetched.push_back(g), r.worker_of.push_back(w);
  }
  turns.pass(batch::GroupTurns::kFetch);
  if (g == fail_slow) std::this_thread::sleep_for(std::chrono::milliseconds(60));
  if (g == fail_at || g == fail_slow) throw Error("group " + std::to_string(g) + " failed");
  std::this_thread::sleep_for(std::chrono::milliseconds(g % 3 == 0 ? 8 : 1));
  turns.check(g);
  turns.wait(batch::GroupTurns::kDone, g);
  {
    std::lock_guard lock(r.mutex);
    r.done.push_back(g);
  }
  turns.pass(batch::GroupTurns::kDone);
}

std::vector<std::size_t> upto(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

}  // namespace

TEST_CASE("Groups in flight: fetched and done in group order on 1, 2 and 3 workers, group g on worker g % n") {
  for (std::size_t workers : {1, 2, 3}) {
    INFO(workers << " workers");
    batch::GroupTurns turns;
    Recorded r;
    std::vector<std::size_t> worker(10);
    batch::run_groups(10, workers, turns, [&](std::size_t g, std::size_t w) {
      worker[g] = w;
      run_group(turns, r, g, w);
    });
    CHECK(r.fetched == upto(10));
    CHECK(r.done == upto(10));
    for (std::size_t g = 0; g < 10; ++g) CHECK(worker[g] == g % workers);
  }
}

TEST_CASE("Groups in flight: the first failing group's error, though a later group failed first in time") {
  for (std::size_t workers : {1, 2, 3}) {
    INFO(workers << " workers");
    batch::GroupTurns turns;
    Recorded r;
    // Group 4 fails after 60 ms, group 5 at once: with several workers 5 fails first in time; 4's error is the one
    // one worker would have met, and groups before 4 still finish and are written.
    CHECK_THROWS_WITH(
        batch::run_groups(12, workers, turns, [&](std::size_t g, std::size_t w) { run_group(turns, r, g, w, 5, 4); }),
        "group 4 failed");
    CHECK(r.done == upto(4));
    for (std::size_t g : r.fetched) CHECK(g <= 4 + workers);  // no group after the failure began later on
  }
}
