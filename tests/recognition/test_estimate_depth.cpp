// Light and full estimates (EstimateDepth, docs/recognition.md "Light and full estimates"): a light estimate is the
// belief's answer without the host's fits, chosen per call, and asking for one changes nothing a full estimate says.
#include <catch2/catch.hpp>

#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include "fixture.hpp"
#include "same_estimate.hpp"
#include "trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

RecognizerOptions cpu_options() {
  RecognizerOptions o;
  o.backend = BackendKind::cpu;
  o.threads = 2;
  return o;
}

}  // namespace

TEST_CASE("Estimate depth: a light estimate is the belief's answer, the full one's bins and modes without its fits") {
  const Trained& t = trained();
  Recognizer r(t.map, paper_space(), cpu_options());
  std::size_t refined = 0, switched = 0;
  for (const Reading& reading : readings_at(2, random_pose(611, 100.0), util::Rng(43), 10)) {
    r.add_reading(reading);
    const Estimate light = r.estimate(5, EstimateDepth::light), full = r.estimate(5, EstimateDepth::full);
    INFO("reading " << r.reading_count());
    REQUIRE(light.ready);
    CHECK_FALSE(light.pose_refined);
    CHECK(same_pose(light.pose, light.parabolic_pose));  // the histogram's pose: no fit ran
    // Stage 1 is the same at both depths: the best bins and the distinct modes, where they lie, bit for bit. (Their
    // probabilities are the objects' posterior's share, which the full estimate's surface check re-weighs.)
    REQUIRE(light.top.size() == full.top.size());
    for (std::size_t i = 0; i < light.top.size(); ++i) {
      CHECK(light.top[i].object == full.top[i].object);
      CHECK(same_pose(light.top[i].pose, full.top[i].pose));
    }
    REQUIRE(light.hypotheses.size() == full.hypotheses.size());
    for (std::size_t i = 0; i < light.hypotheses.size(); ++i) {
      CHECK(light.hypotheses[i].object == full.hypotheses[i].object);
      CHECK(light.hypotheses[i].covariance == full.hypotheses[i].covariance);
      if (i > 0 || !full.pose_refined) CHECK(same_pose(light.hypotheses[i].pose, full.hypotheses[i].pose));
    }
    if (!full.pose_refined) CHECK(light.object_probability == full.object_probability);  // no surface bits yet
    if (full.object == light.object) CHECK(same_pose(full.parabolic_pose, light.parabolic_pose));
    refined += full.pose_refined ? 1 : 0;
    switched += full.object != light.object ? 1 : 0;
  }
  CHECK(refined > 0);    // not vacuous: the full estimates fitted (from 6 readings on)
  CHECK(switched == 0);  // on this session the surface check agrees with the belief: the parabolic poses compared
}

TEST_CASE(
    "Estimate depth: light equals a recognizer built without fits, and a full estimate after it equals one alone") {
  const Trained& t = trained();
  RecognizerOptions without_fits = cpu_options();
  without_fits.refine_pose = false;
  without_fits.surface_check = false;
  // Two sessions on one batch recognizer asked in two orders, a third that never fits.
  BatchRecognizer both(t.map, paper_space(), 2, cpu_options());
  Recognizer bare(t.map, paper_space(), without_fits);
  const std::size_t ids[] = {0, 1};
  std::size_t step = 0;
  for (const Reading& reading : readings_at(1, random_pose(97, 100.0), util::Rng(97), 9)) {
    const Reading pair[] = {reading, reading};
    both.add_readings(ids, pair);
    bare.add_reading(reading);
    INFO("reading " << ++step);
    const Estimate light = both.estimate(0, 3, EstimateDepth::light);
    CHECK(same(light, bare.estimate(3)));
    const Estimate full_after_light = both.estimate(0, 3, EstimateDepth::full);
    const Estimate full_alone = both.estimate(1, 3);  // session 1 is never asked a light estimate
    CHECK(same(full_after_light, full_alone));
    // A batch's light estimates, each session's own.
    const std::vector<Estimate> batch = both.estimates(ids, 3, EstimateDepth::light);
    CHECK(same(batch[0], light));
    CHECK(same(batch[1], light));
  }
  CHECK(both.estimate(0, 3).pose_refined);  // the full depth fitted: the two depths differ
}

TEST_CASE("Estimate depth: names parse both ways, anything else is refused naming the option") {
  for (EstimateDepth d : {EstimateDepth::full, EstimateDepth::light})
    CHECK(parse_estimate_depth(estimate_depth_name(d), "test") == d);
  CHECK_THROWS_WITH(parse_estimate_depth("fine", "sva eval: --estimate"),
                    Catch::Contains("sva eval: --estimate") && Catch::Contains("\"fine\""));
  CHECK_THROWS_AS(parse_estimate_depth("", "x"), Error);
}
