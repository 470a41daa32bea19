// How many sessions a batch steps together by default (Engine::sessions_per_submission, issue 52): on a GPU as many
// as half its memory left by the map holds with every session's belief at its bound, from 64 to 4096; 64 on a CPU.
#include <catch2/catch.hpp>

#include <sva/engine.hpp>
#include <sva/error.hpp>

#include "backends/vulkan/gpu_belief.hpp"
#include "recognition/engine.hpp"
#include "recognition/engine_access.hpp"
#include "recognition/trained_map.hpp"

using namespace sva;

namespace {
constexpr std::uint64_t kGiB = std::uint64_t{1} << 30;
}

TEST_CASE("submission size: a GPU's memory holds the batch's beliefs at their bound, within the limits") {
  const std::uint64_t belief = GpuBelief::bytes_at(std::size_t{1} << 22, 10);  // the default budget, 10 objects
  // A table of 2^23 slots (half full at 2^22 bins): keys and offsets, band marks and the band list's two sides.
  CHECK(belief >= (std::uint64_t{1} << 23) * 24);
  CHECK(belief < (std::uint64_t{1} << 23) * 25);
  for (const std::uint64_t memory : {16 * kGiB, 80 * kGiB, 141 * kGiB}) {
    INFO("device memory " << memory / kGiB << " GiB");
    const std::uint64_t map = 90'000'000;
    const std::size_t n = submission_sessions({"discrete", memory, map, belief});
    REQUIRE(n >= kMinSubmission);
    REQUIRE(n <= kMaxSubmission);
    // Half of what the map leaves holds both groups in flight; one more session each would not fit (unless the
    // floor of 64 decided).
    CHECK(in_flight({"discrete", memory, map, belief}) == 2);
    if (n > kMinSubmission) CHECK(2 * n * belief <= (memory - map) / 2);
    if (n > kMinSubmission && n < kMaxSubmission) CHECK(2 * (n + 1) * belief > (memory - map) / 2);
  }
  // An H100's 80 GiB holds about a hundred sessions per group at the default bound, two groups in flight.
  const std::size_t h100 = submission_sessions({"discrete", 80 * kGiB, 90'000'000, belief});
  CHECK(h100 > 64);
  CHECK(h100 < 200);
  // A small bound fills a large device up to the ceiling.
  CHECK(submission_sessions({"discrete", 141 * kGiB, 0, GpuBelief::bytes_at(32768, 10)}) == kMaxSubmission);
}

TEST_CASE("submission size: 64 on a CPU, without a bound, or when the map leaves no memory") {
  const std::uint64_t belief = GpuBelief::bytes_at(1 << 20, 3);
  CHECK(submission_sessions({"", 0, 0, 0}) == kMinSubmission);                         // the CPU reference
  CHECK(submission_sessions({"cpu", 64 * kGiB, 0, belief}) == kMinSubmission);         // lavapipe: the host's cores
  CHECK(submission_sessions({"discrete", 64 * kGiB, 0, 0}) == kMinSubmission);         // no bound on a belief
  CHECK(submission_sessions({"discrete", kGiB, 2 * kGiB, belief}) == kMinSubmission);  // the map fills it
  CHECK(submission_sessions({"integrated", 4 * kGiB, 0, belief}) == kMinSubmission);   // the floor
  // One group in flight on a CPU: the one already fills its cores.
  CHECK(in_flight({"", 0, 0, 0}) == 1);
  CHECK(in_flight({"cpu", 64 * kGiB, 0, belief}) == 1);
  CHECK(in_flight({"integrated", 4 * kGiB, 0, belief}) == 2);
}

TEST_CASE("submission size: an engine steps 64 sessions on a CPU or lavapipe, its device's share on a GPU") {
  const sva::test::Trained& t = sva::test::trained();
  CHECK(Engine(t.map, {BackendKind::cpu, ""}).sessions_per_submission() == kMinSubmission);
  CHECK(Engine(t.map, {BackendKind::cpu, ""}).submissions_in_flight() == 1);
  try {
    const Engine gpu(t.map, {BackendKind::vulkan, ""});
    const Engine::Impl& impl = *EngineAccess::impl(gpu);
    INFO("device " << gpu.backend_description() << ", type '" << impl.device_type << "'");
    REQUIRE(!impl.device_type.empty());
    if (impl.device_type == "cpu") {  // lavapipe: the host's cores, as the CPU reference
      CHECK(gpu.sessions_per_submission() == kMinSubmission);
      CHECK(gpu.submissions_in_flight() == 1);
    } else {  // a GPU (an H200 took 186): its memory as the backend found it, the map's upload within it
      REQUIRE(impl.device_memory_bytes > impl.map_device_bytes);
      REQUIRE(impl.map_device_bytes > 0);
      const RecognizerOptions options;
      const std::uint64_t belief = GpuBelief::bytes_at(options.belief_budget_bins, impl.keep_space->objects());
      CHECK(gpu.sessions_per_submission(options) ==
            submission_sessions({impl.device_type, impl.device_memory_bytes, impl.map_device_bytes, belief}));
      CHECK(gpu.submissions_in_flight() == 2);
    }
  } catch (const Error& e) {
    WARN("no Vulkan device: " << e.what());
  }
}
