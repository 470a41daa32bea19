// A recognizer's answers do not depend on the floating-point environment of the thread that calls it
// (sva/base/float_environment.hpp): a caller that flushes subnormal numbers to zero, as Embree's builds and
// -ffast-math libraries leave threads, gets the same estimates bit for bit, and its own environment back.
#include <catch2/catch.hpp>

#include <sva/base/float_environment.hpp>
#include <sva/recognizer.hpp>

#include "base/flush_to_zero.hpp"
#include "recognition/fixture.hpp"
#include "recognition/same_estimate.hpp"
#include "recognition/trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

// Runs fn with the calling thread's flush-to-zero on; false where the test cannot reach such a switch.
template <class Fn>
bool flushing(Fn fn) {
  if (!set_flush_to_zero(true)) return false;
  fn();
  set_flush_to_zero(false);
  return true;
}

}  // namespace

TEST_CASE("a caller that flushes subnormals to zero gets the same estimates, and keeps its own environment") {
  const Trained& t = trained();
  for (const unsigned threads : {1u, 2u}) {
    RecognizerOptions options;
    options.backend = BackendKind::cpu;
    options.threads = threads;
    for (std::uint32_t object = 0; object < 3; ++object) {
      const std::vector<Reading> readings =
          readings_at(object, random_pose(900 + object, 100.0), util::Rng(900 + object, 5), 16);
      Recognizer standard(t.map, paper_space(), options), flushed(t.map, paper_space(), options);
      std::vector<Estimate> expected, got;
      for (const Reading& r : readings) {
        standard.add_reading(r);
        expected.push_back(standard.estimate(3));
      }
      bool kept = true;
      const bool ran = flushing([&] {
        for (const Reading& r : readings) {
          flushed.add_reading(r);
          got.push_back(flushed.estimate(3));
          kept = kept && !util::standard_floats();  // the caller's flush-to-zero is back after each call
        }
      });
      if (!ran) return;  // no flush-to-zero on this CPU
      INFO(threads << " threads, object " << object);
      CHECK(kept);
      REQUIRE(got.size() == expected.size());
      for (std::size_t i = 0; i < got.size(); ++i) CHECK(same(got[i], expected[i]));
      // Not vacuous: the fits and the surface check ran, and at 16 readings the hypotheses' covariances hold
      // subnormal terms (these sessions' estimates differed under a flushing caller before 2026-11-30).
      CHECK(expected.back().pose_refined);
    }
  }
}
