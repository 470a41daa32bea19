// A batch's estimates at once (BatchRecognizer::estimates, issue 52): several hundred sessions stepped together
// must each get exactly what a recognizer of their own gets, and estimates() what estimate() gives, for any thread
// count: the sessions' fits run side by side on the workers, the CPU belief's reductions too.
#include <catch2/catch.hpp>

#include <sva/batch_recognizer.hpp>
#include <sva/recognizer.hpp>

#include <cmath>
#include <numeric>

#include "recognition/fixture.hpp"
#include "recognition/same_estimate.hpp"
#include "recognition/trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// Session i: 0 to 7 readings of object i mod 3 at its own pose (a session with none is "not ready").
std::vector<Reading> session_readings(std::size_t i) {
  return readings_at(static_cast<std::uint32_t>(i % 3), random_pose(400 + i, 100.0), util::Rng(400 + i, 5),
                     static_cast<int>(i % 8));
}

}  // namespace

TEST_CASE("a batch of several hundred sessions gives each session what it gets alone, its estimates at once") {
  const Trained& t = trained();
  constexpr std::size_t kSessions = 320;
  std::vector<std::vector<Reading>> readings(kSessions);
  std::size_t longest = 0;
  for (std::size_t i = 0; i < kSessions; ++i) {
    readings[i] = session_readings(i);
    longest = std::max(longest, readings[i].size());
  }
  RecognizerOptions options;
  options.backend = BackendKind::cpu;
  options.threads = 2;
  BatchRecognizer batch(t.map, paper_space(), kSessions, options);
  for (std::size_t step = 0; step < longest; ++step) {  // lock-step: every session with a reading left gets it
    std::vector<std::size_t> ids;
    std::vector<Reading> rd;
    for (std::size_t i = 0; i < kSessions; ++i)
      if (step < readings[i].size()) {
        ids.push_back(i);
        rd.push_back(readings[i][step]);
      }
    batch.add_readings(ids, rd);
  }
  std::vector<std::size_t> all(kSessions);
  std::iota(all.begin(), all.end(), std::size_t{0});
  const std::vector<Estimate> at_once = batch.estimates(all, 3);
  REQUIRE(at_once.size() == kSessions);
  // Alone: a recognizer per session (every 7th, to keep the test short), on 1 thread.
  RecognizerOptions one = options;
  one.threads = 1;
  std::size_t compared = 0, refined = 0;
  for (std::size_t i = 0; i < kSessions; i += 7) {
    Recognizer alone(t.map, paper_space(), one);
    for (const Reading& r : readings[i]) alone.add_reading(r);
    INFO("session " << i << " of " << readings[i].size() << " readings");
    CHECK(same(at_once[i], alone.estimate(3)));
    CHECK(same(at_once[i], batch.estimate(i, 3)));
    ++compared;
    refined += at_once[i].pose_refined;
  }
  // Any order and subset of sessions: each answer is its own session's.
  const std::vector<std::size_t> some = {301, 5, 64, 0, 77};
  const std::vector<Estimate> subset = batch.estimates(some, 3);
  for (std::size_t k = 0; k < some.size(); ++k) CHECK(same(subset[k], at_once[some[k]]));
  CHECK_THROWS_WITH(batch.estimates(std::vector<std::size_t>{3, kSessions}, 3), Catch::Contains("out of range"));
  // Not vacuous: sessions without readings, with a few, and with fine poses were compared.
  CHECK(compared > 40);
  CHECK(refined > 5);
  CHECK_FALSE(at_once[0].ready);
  CHECK(at_once[14].ready);
}

TEST_CASE("a batch's estimates say where their time went, stage by stage, over the sessions that ran the stages") {
  const Trained& t = trained();
  RecognizerOptions options;
  options.backend = BackendKind::cpu;
  options.threads = 2;
  BatchRecognizer batch(t.map, paper_space(), 4, options);
  CHECK(batch.last_estimate_timing().sessions == 0);  // no estimate yet
  // Sessions 0-2 get 7 readings (the fine pose and the surface check run from 6), session 3 none.
  for (std::size_t step = 0; step < 7; ++step) {
    std::vector<std::size_t> ids{0, 1, 2};
    std::vector<Reading> rd;
    for (std::size_t i : ids) rd.push_back(session_readings(7 + 8 * i)[step]);
    batch.add_readings(ids, rd);
  }
  const std::vector<std::size_t> all{0, 1, 2, 3};
  const std::vector<Estimate> est = batch.estimates(all, 3);
  REQUIRE(est.size() == 4);
  REQUIRE(est[0].pose_refined);
  const BatchRecognizer::EstimateTiming took = batch.last_estimate_timing();
  CHECK(took.sessions == 3);  // the session without readings runs no stage
  for (double ms : {took.belief_ms, took.fit_ms, took.verify_ms, took.posterior_ms}) {
    CHECK(std::isfinite(ms));
    CHECK(ms >= 0.0);
  }
  CHECK(took.belief_ms > 0.0);
  CHECK(took.fit_ms > 0.0);     // three fine poses
  CHECK(took.verify_ms > 0.0);  // and their surface checks
  // Another call replaces the figures: one session alone.
  (void)batch.estimate(1, 3);
  CHECK(batch.last_estimate_timing().sessions == 1);
  (void)batch.estimate(3, 3);  // no readings: no stage ran, none is left from the call before
  CHECK(batch.last_estimate_timing().sessions == 0);
  CHECK(batch.last_estimate_timing().fit_ms == 0.0);
}

TEST_CASE("a batch refuses the first bad reading in its sessions' order, whatever the thread count, changing nothing") {
  // The readings are described on the workers (BatchRecognizer::Impl::describe); with two bad ones the refusal must
  // still name the first, and no session may have taken its reading.
  const Trained& t = trained();
  for (const unsigned threads : {1u, 2u, 16u}) {
    RecognizerOptions options;
    options.backend = BackendKind::cpu;
    options.threads = threads;
    BatchRecognizer batch(t.map, paper_space(), 4, options);
    std::vector<Reading> rd;
    for (std::size_t i = 0; i < 4; ++i) rd.push_back(session_readings(1).front());
    batch.add_readings(std::vector<std::size_t>{0, 1, 2, 3}, rd);
    const Estimate before = batch.estimate(2, 3);
    rd[1].pressure.front() = std::nanf("");
    rd[3].status = ControllerStatus::not_converged;
    INFO(threads << " threads");
    CHECK_THROWS_WITH(batch.add_readings(std::vector<std::size_t>{3, 2, 1, 0}, rd),
                      Catch::Contains("session 2, reading 2: the pressure image has a non-finite value"));
    CHECK_THROWS_WITH(batch.add_readings(std::vector<std::size_t>{0, 1, 2, 3}, rd),
                      Catch::Contains("session 1, reading 2: the pressure image has a non-finite value"));
    std::swap(rd[1], rd[3]);
    CHECK_THROWS_WITH(batch.add_readings(std::vector<std::size_t>{0, 1, 2, 3}, rd),
                      Catch::Contains("session 1, reading 2: the contact controller did not converge"));
    CHECK(same(batch.estimate(2, 3), before));
    CHECK(batch.estimate(0, 3).readings == 1);
  }
}
