// A batch's estimates at once on the Vulkan backend (BatchRecognizer::estimates, issue 52): the belief is read one
// session at a time on the device, the fits then run on the host's workers; each session's answer must be what
// estimate() gives and what the CPU reference's batch gives, bit for bit.
#include <catch2/catch.hpp>

#include <sva/batch_file.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>

#include <cstdlib>
#include <numeric>

#include "backends/vulkan/faults.hpp"
#include "recognition/batch_sessions.hpp"
#include "recognition/fixture.hpp"
#include "recognition/same_estimate.hpp"
#include "recognition/trained_map.hpp"
#include "vk_test_support.hpp"

using namespace sva;
using namespace sva::test;

namespace {

constexpr std::size_t kSessions = 40;

// The options of the tests' batches: Vulkan, two workers.
RecognizerOptions gpu_options() {
  RecognizerOptions vo;
  vo.backend = BackendKind::vulkan;
  vo.threads = 2;
  return vo;
}

// A batch of kSessions on the Vulkan backend; the test is skipped where no device is usable.
std::unique_ptr<BatchRecognizer> gpu_batch() {
  try {
    return std::make_unique<BatchRecognizer>(trained().map, paper_space(), kSessions, gpu_options());
  } catch (const Error& e) {
    skip(e.what());
  }
}

// The same with the device's memory staged, as on a discrete GPU (SVA_VK_STAGING, read when the engine is made).
std::unique_ptr<BatchRecognizer> staged_gpu_batch() {
  ::setenv("SVA_VK_STAGING", "1", 1);
  try {
    std::unique_ptr<BatchRecognizer> b = gpu_batch();
    ::unsetenv("SVA_VK_STAGING");
    return b;
  } catch (...) {
    ::unsetenv("SVA_VK_STAGING");
    throw;
  }
}

}  // namespace

TEST_CASE("GPU batch: the estimates of 40 sessions at once equal estimate() and the CPU reference's") {
  const std::unique_ptr<BatchRecognizer> gpu = gpu_batch();
  RecognizerOptions co = gpu_options();
  co.backend = BackendKind::cpu;
  BatchRecognizer cpu(trained().map, paper_space(), kSessions, co);
  for (std::size_t step = 0; step < 7; ++step) {
    std::vector<std::size_t> ids;
    std::vector<Reading> rd;
    for (std::size_t i = 0; i < kSessions; ++i) {
      const std::vector<Reading> r = readings_at(static_cast<std::uint32_t>(i % 3), random_pose(700 + i, 100.0),
                                                 util::Rng(700 + i, 5), static_cast<int>(i % 8));
      if (step >= r.size()) continue;
      ids.push_back(i);
      rd.push_back(r[step]);
    }
    gpu->add_readings(ids, rd);
    cpu.add_readings(ids, rd);
  }
  std::vector<std::size_t> all(kSessions);
  std::iota(all.begin(), all.end(), std::size_t{0});
  const std::vector<Estimate> g = gpu->estimates(all, 3), c = cpu.estimates(all, 3);
  std::size_t refined = 0;
  for (std::size_t i = 0; i < kSessions; ++i) {
    INFO("session " << i);
    CHECK(same(g[i], c[i]));
    CHECK(same(g[i], gpu->estimate(i, 3)));
    refined += g[i].pose_refined;
  }
  CHECK(refined > 5);  // not vacuous: fine poses were fitted on the workers
}

TEST_CASE("GPU batch: a batch's estimates read every session's belief in two submissions") {
  // The read-ahead (VoteBackend::read_ahead, look_up_ahead) runs each belief pass once for all sessions: the stale
  // bands, the summaries with the best bins (the device picks their bucket), then the bins read by key of 40 sessions
  // cost two submissions where each session's estimate made its own round trips. Staged too, as on a discrete GPU,
  // whose device memory the host does not map: each pass's results come back in its own submission, not in a download
  // per session after it.
  const bool staged = GENERATE(false, true);
  INFO((staged ? "staged" : "mapped") << " device memory");
  const std::unique_ptr<BatchRecognizer> batch = staged ? staged_gpu_batch() : gpu_batch();
  const std::unique_ptr<BatchRecognizer> alone = staged ? staged_gpu_batch() : gpu_batch();
  for (std::size_t step = 0; step < 4; ++step) {
    std::vector<std::size_t> ids(kSessions);
    std::iota(ids.begin(), ids.end(), std::size_t{0});
    std::vector<Reading> rd;
    for (std::size_t i = 0; i < kSessions; ++i)
      rd.push_back(
          readings_at(static_cast<std::uint32_t>(i % 3), random_pose(900 + i, 100.0), util::Rng(900 + i, 5), 4)[step]);
    batch->add_readings(ids, rd);
    alone->add_readings(ids, rd);
  }
  std::vector<std::size_t> all(kSessions);
  std::iota(all.begin(), all.end(), std::size_t{0});
  const std::uint64_t b0 = batch->device_submissions();
  const std::vector<Estimate> together = batch->estimates(all, 3);
  const std::uint64_t batched = batch->device_submissions() - b0;
  const std::uint64_t a0 = alone->device_submissions();
  for (std::size_t i = 0; i < kSessions; ++i) {
    INFO("session " << i);
    CHECK(same(together[i], alone->estimate(i, 3)));
  }
  const std::uint64_t each = alone->device_submissions() - a0;
  INFO("submissions: " << batched << " for the batch, " << each << " one session at a time");
  CHECK(batched > 0);
  // Alone, a session reads its summary with its best bins (past the band too: the table's passes join them, staged;
  // on lavapipe's mapped memory the host reads that table itself), then its bins by key: two round trips each.
  // Staged, a batch took two round trips a session before its reads came back in the passes' submissions, and four
  // in all before the device picked the best bins' bucket; a third where a band list was lost and read again.
  CHECK(each >= 2 * kSessions);
  CHECK(batched <= 3);
}

TEST_CASE("GPU batch: a robot's touch is one round trip once an estimate has read its session") {
  // After an estimate, the next update's submission also reads what the next estimate reads first (the summary, the
  // best bins) and chooses the bins it reads by key on the device (belief_hoods.comp): the estimate then reads
  // nothing. Each answer is the CPU reference's; top_k 5 chooses modes among the best bins, 1 the best bin alone, 0
  // none. Staged, as on a discrete GPU; a touch that grows its table (early on) costs a submission more.
  // With a pose prior (a robot that knows roughly where the object lies) the device orders the modes and picks the
  // objects' best bins under it too, in floats: the host checks its list against the device's.
  const auto [staged, top_k, with_prior] = GENERATE(
      table<bool, std::size_t, bool>({{true, 5, false}, {true, 0, false}, {false, 1, false}, {true, 3, true}}));
  INFO((staged ? "staged" : "mapped") << ", top_k " << top_k << (with_prior ? ", pose prior" : ""));
  const std::unique_ptr<BatchRecognizer> gpu = staged ? staged_gpu_batch() : gpu_batch();
  RecognizerOptions co = gpu_options();
  co.backend = BackendKind::cpu;
  BatchRecognizer cpu(trained().map, paper_space(), 1, co);
  const std::size_t session = 0;
  const RigidPose truth = random_pose(950, 100.0);
  const std::vector<Reading> rd = readings_at(1, truth, util::Rng(950, 5), 9);
  if (with_prior) {
    Prior prior;
    prior.object_pose.resize(3);
    PosePrior near;
    near.position = truth.T + glm::dvec3(15.0, -10.0, 5.0);
    near.position_sigma_mm = 20.0;
    near.has_rotation = true;
    near.rotation = truth.R;
    near.rotation_sigma_rad = 0.4;
    prior.object_pose[1] = near;
    PosePrior elsewhere;
    elsewhere.position = truth.T - glm::dvec3(40.0, 30.0, 0.0);
    elsewhere.position_sigma_mm = 25.0;
    prior.object_pose[2] = elsewhere;
    gpu->set_prior(session, prior);
    cpu.set_prior(session, prior);
  }
  std::size_t read_nothing = 0, touches = 0;
  for (std::size_t r = 0; r < rd.size(); ++r) {
    INFO("reading " << r + 1);
    gpu->add_readings(std::span(&session, 1), std::span(&rd[r], 1));
    cpu.add_readings(std::span(&session, 1), std::span(&rd[r], 1));
    const std::uint64_t s0 = gpu->device_submissions();
    const Estimate g = gpu->estimate(session, top_k);
    const std::uint64_t reads = gpu->device_submissions() - s0;
    CHECK(same(g, cpu.estimate(session, top_k)));
    if (r < 2) continue;  // the first pair's estimate reads alone
    ++touches;
    read_nothing += reads == 0 ? 1 : 0;
  }
  INFO(read_nothing << " of " << touches << " estimates read nothing");
  // Every estimate after the second pair reads its session in the update's submission. On lavapipe's mapped memory
  // (a CPU device) the host reads the table itself where the modes' candidates lie past the band, and then looks up
  // its keys alone.
  if (staged || top_k <= 1) CHECK(read_nothing == touches);
}

TEST_CASE(
    "GPU batch: groups in flight on two recognizers of one device give each session the one recognizer's answer") {
  // 30 sessions in groups of 8 on two recognizers of one Vulkan engine at once (their submissions take turns on the
  // device's queue while the other's host work runs), against one recognizer on the CPU reference.
  std::vector<BatchSession> sessions(30);
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    sessions[i].id = std::to_string(i);
    sessions[i].readings = readings_at(static_cast<std::uint32_t>(i % 3), random_pose(900 + i, 100.0),
                                       util::Rng(900 + i, 5), 2 + static_cast<int>(i % 5));
  }
  std::unique_ptr<Engine> engine;
  try {
    engine = std::make_unique<Engine>(trained().map, EngineOptions{BackendKind::vulkan, ""});
  } catch (const Error& e) {
    skip(e.what());
  }
  std::vector<BatchRecognizer> gpu = batch_recognizers(*engine, sessions.size(), 8, 2, gpu_options());
  REQUIRE(gpu.size() == 2);
  RecognizerOptions co = gpu_options();
  co.backend = BackendKind::cpu;
  BatchRecognizer cpu(trained().map, paper_space(), 8, co);
  const auto a = batch::recognize_sessions(gpu, sessions, {.top_k = 3}, "gpu");
  const auto b = batch::recognize_sessions(std::span(&cpu, 1), sessions, {.top_k = 3}, "cpu");
  REQUIRE(a.size() == sessions.size());
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    INFO("session " << i);
    CHECK(same(a[i], b[i]));
  }
  CHECK(gpu[1].readings(0) == sessions[24].readings.size());  // not vacuous: the second ran groups 1 and 3
}

TEST_CASE("GPU batch: a group's sessions reset together in one submission, then recognise as new sessions do") {
  // BatchRecognizer::reset of many sessions (a group's start in sva recognize and sva eval): their beliefs are emptied
  // in one submission, where each session's reset was one or two round trips of its own (issue 52). Staged, as on a
  // discrete GPU. A bad id changes nothing.
  const std::unique_ptr<BatchRecognizer> used = staged_gpu_batch(), fresh = staged_gpu_batch();
  std::vector<std::size_t> all(kSessions);
  std::iota(all.begin(), all.end(), std::size_t{0});
  const auto feed = [&](BatchRecognizer& b, std::uint64_t seed, int steps) {
    for (int step = 0; step < steps; ++step) {
      std::vector<Reading> rd;
      for (std::size_t i = 0; i < kSessions; ++i)
        rd.push_back(readings_at(static_cast<std::uint32_t>(i % 3), random_pose(seed + i, 100.0),
                                 util::Rng(seed + i, 5), steps)[static_cast<std::size_t>(step)]);
      b.add_readings(all, rd);
    }
  };
  feed(*used, 500, 4);
  const std::vector<std::size_t> bad{3, kSessions};
  CHECK_THROWS_AS(used->reset(bad), Error);
  CHECK(used->readings(3) == 4);  // untouched: every id is checked first
  const std::uint64_t before = used->device_submissions();
  used->reset(all);
  CHECK(used->device_submissions() - before == 1);
  for (std::size_t i : all) CHECK(used->readings(i) == 0);
  feed(*used, 1100, 3);
  feed(*fresh, 1100, 3);
  const std::vector<Estimate> a = used->estimates(all, 3), b = fresh->estimates(all, 3);
  for (std::size_t i = 0; i < kSessions; ++i) {
    INFO("session " << i);
    CHECK(same(a[i], b[i]));
  }
}

TEST_CASE("GPU batch: light estimates after every touch and a full one when asked, each the CPU reference's") {
  // A robot's answer after every touch without the host's fits (EstimateDepth::light), and the full estimate at some
  // touches. Both depths read the same summary, best bins and keys (a full estimate's fits start from the best bins
  // the modes already read), so after the second pair each is answered by what the update read ahead: no round trip
  // of its own at either depth, staged as on a discrete GPU.
  const std::unique_ptr<BatchRecognizer> gpu = staged_gpu_batch();
  RecognizerOptions co = gpu_options();
  co.backend = BackendKind::cpu;
  BatchRecognizer cpu(trained().map, paper_space(), 1, co);
  const std::size_t session = 0;
  const std::vector<Reading> rd = readings_at(2, random_pose(960, 100.0), util::Rng(960, 5), 9);
  std::size_t estimates = 0, read_nothing = 0, refined = 0;
  for (std::size_t r = 0; r < rd.size(); ++r) {
    INFO("reading " << r + 1);
    gpu->add_readings(std::span(&session, 1), std::span(&rd[r], 1));
    cpu.add_readings(std::span(&session, 1), std::span(&rd[r], 1));
    for (EstimateDepth depth : {EstimateDepth::light, EstimateDepth::full}) {
      if (depth == EstimateDepth::full && r != 5 && r != 6 && r != 8) continue;
      INFO(estimate_depth_name(depth));
      const std::uint64_t s0 = gpu->device_submissions();
      const Estimate g = gpu->estimate(session, 3, depth);
      const std::uint64_t reads = gpu->device_submissions() - s0;
      CHECK(same(g, cpu.estimate(session, 3, depth)));
      if (depth == EstimateDepth::light) CHECK_FALSE(g.pose_refined);
      refined += g.pose_refined ? 1 : 0;
      if (r < 2) continue;  // the first pair's estimate reads alone
      ++estimates;
      read_nothing += reads == 0 ? 1 : 0;
    }
  }
  CHECK(refined > 0);  // not vacuous: the full estimates fitted
  INFO(read_nothing << " of " << estimates << " estimates read nothing");
  CHECK(estimates == 10);
  CHECK(read_nothing == estimates);
}

namespace {

// Three readings of object i mod 3 at its own pose (seeded by `seed` + i) into every session of `gpu` and of a CPU
// reference's batch of as many; then every `every`-th session's estimate on both must be the same.
void same_as_cpu_after_three_readings(BatchRecognizer& gpu, std::uint64_t seed, std::size_t every) {
  const std::size_t n = gpu.sessions();
  RecognizerOptions co = gpu_options();
  co.backend = BackendKind::cpu;
  BatchRecognizer cpu(trained().map, paper_space(), n, co);
  std::vector<std::size_t> ids(n);
  std::iota(ids.begin(), ids.end(), std::size_t{0});
  for (std::size_t step = 0; step < 3; ++step) {
    std::vector<Reading> rd;
    for (std::size_t i = 0; i < n; ++i)
      rd.push_back(readings_at(static_cast<std::uint32_t>(i % 3), random_pose(seed + i, 100.0), util::Rng(seed + i, 5),
                               3)[step]);
    gpu.add_readings(ids, rd);
    cpu.add_readings(ids, rd);
  }
  for (std::size_t i = 0; i < n; i += every) {
    INFO("session " << i);
    CHECK(same(gpu.estimate(i, 1), cpu.estimate(i, 1)));
  }
}

}  // namespace

TEST_CASE("GPU batch: 320 sessions live in a few memory allocations, under a driver's cap of 32, each as on the CPU") {
  // Every session holds a belief table, a band list and a state on the device (and, once estimated, the buffers of
  // its reads): one allocation each was 960 and more here, and a batch of about 400 passed the 4096 live
  // allocations many drivers allow (maxMemoryAllocationCount). The buffers share the memory pool's blocks
  // (backends/vulkan/memory_pool.hpp): a cap of 32 live allocations, injected, holds them all (with a buffer per
  // allocation, this batch failed at its construction: "out of memory allocations"). The count takes in the
  // estimates' reads too. Every eighth session's estimate is the CPU reference batch's, whose sessions answer as
  // alone ("a batch of several hundred sessions gives each session what it gets alone", tests/recognition).
  struct Cleared {
    ~Cleared() { vk::faults::set_max_allocations(0); }
  } cleared;
  // Skipped where no device is usable; from here on, an error fails the test. The probe shares the map's engine
  // with the batch below: the device's allocations are counted from here.
  const std::unique_ptr<BatchRecognizer> probe = gpu_batch();
  const std::uint64_t a0 = probe->device_allocations();
  vk::faults::set_max_allocations(32);
  constexpr std::size_t kMany = 320;
  const auto gpu = std::make_unique<BatchRecognizer>(trained().map, paper_space(), kMany, gpu_options());
  same_as_cpu_after_three_readings(*gpu, 1200, 8);
  const std::uint64_t made = gpu->device_allocations() - a0;
  CHECK(made > 0);   // the sessions' tables took new blocks, counted
  CHECK(made < 32);  // and far fewer than their 960 buffers
}

TEST_CASE("GPU batch: a new batch's sessions empty their beliefs in one submission, and answer as the CPU's") {
  // Each new belief emptied its table in a round trip of its own: a batch of a thousand sessions made a thousand
  // before its first update (VoteBackend::make_beliefs). The probe shares the map's engine, whose round trips it
  // counts: those of every recognizer on the device.
  const std::unique_ptr<BatchRecognizer> probe = gpu_batch();
  const std::uint64_t s0 = probe->device_submissions();
  const std::unique_ptr<BatchRecognizer> gpu = gpu_batch();
  CHECK(probe->device_submissions() - s0 == 1);
  same_as_cpu_after_three_readings(*gpu, 1600, 5);
}
