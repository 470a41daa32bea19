// util::Pool (sva/base/pool.hpp): a parallel loop's workers borrow objects that are expensive to make, and the pool
// makes no more of them than were in use at once.
#include <catch2/catch.hpp>

#include <sva/base/parallel.hpp>
#include <sva/base/pool.hpp>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

using sva::util::Pool;

TEST_CASE("a pool lends back what was given back, and makes one only when none is free") {
  int made = 0;
  Pool<int> pool([&] { return std::make_unique<int>(++made); });
  std::unique_ptr<int> a = pool.take(), b = pool.take();
  CHECK(made == 2);
  CHECK(*a == 1);
  CHECK(*b == 2);
  int* kept = a.get();
  pool.give_back(std::move(a));
  CHECK(pool.free() == 1);
  std::unique_ptr<int> c = pool.take();
  CHECK(c.get() == kept);  // the one given back, not a new one
  CHECK(made == 2);
  CHECK(pool.free() == 0);
}

TEST_CASE("a pool's factory that makes nothing is an error, not a null object") {
  Pool<int> pool([] { return std::unique_ptr<int>(); });
  CHECK_THROWS_AS(pool.take(), std::logic_error);
}

TEST_CASE("a parallel loop borrowing from a pool makes at most one object per worker, each in one use at a time") {
  std::atomic<int> made{0};
  Pool<std::atomic<int>> pool([&] {
    ++made;
    return std::make_unique<std::atomic<int>>(0);
  });
  std::atomic<bool> shared{false};
  const unsigned threads = 3;
  sva::util::parallel_for(
      200,
      [&](std::size_t) {
        std::unique_ptr<std::atomic<int>> t = pool.take();
        if (t->fetch_add(1) != 0) shared = true;  // another worker holds it now
        std::this_thread::yield();                // let another worker take its turn meanwhile
        t->fetch_sub(1);
        pool.give_back(std::move(t));
      },
      threads);
  CHECK_FALSE(shared);
  CHECK(made.load() >= 1);
  CHECK(made.load() <= static_cast<int>(threads));
  CHECK(pool.free() == static_cast<std::size_t>(made.load()));
}
