// Recognition on Embree-simulated readings with the realistic errors on (sva
// issue 10): three paper3d objects, 60 training readings each, read by one
// physical sensor and tested with another, the arm's pose errors on every
// reading. Small enough to simulate, train and evaluate in seconds, large
// enough that accuracy and the fine pose decide something. The ladder of error
// levels (`--error-scale`) is checked here too.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>
#include <sva/sim/simulate.hpp>

#include <algorithm>

#include <sva/eval/evaluation.hpp>
#include <sva/eval/results.hpp>
#include "map/map_builder.hpp"
#include "test_support.hpp"

using namespace sva;

namespace {

// die, mug and knight of paper3d (none symmetric, so every pose error counts),
// with paper3d's realistic errors block.
Scene three_objects() {
  Scene s = load_scene("paper3d");
  std::vector<SceneObject> keep;
  for (const auto& o : s.objects)
    if (o.name == "die" || o.name == "mug" || o.name == "knight") keep.push_back(o);
  s.objects = keep;
  s.name = "paper3d-three";
  return s;
}

eval::Curve evaluate(double error_scale) {
  sim::SimulateOptions so;
  so.train_per_object = 60;
  so.test_per_object = 20;
  so.seed = test::scenario_seed(7);
  so.error_scale = error_scale;
  const sim::SimulatedData data = sim::simulate(three_objects(), so);
  TrainOptions to;
  to.clusters = 8;
  const Map map = Map::train(data.train, to);
  eval::EvalOptions eo;
  eo.trials = 12;  // 4 per object
  eo.max_readings = 12;
  eo.seed = test::scenario_seed(2);
  eo.progress = false;
  return eval::summarize(eval::run_evaluation(map, data.test, eo));
}

}  // namespace

TEST_CASE("errors: the realistic errors block of paper3d is what the accuracy test runs on") {
  const ErrorModel e = three_objects().errors;
  CHECK(e.position_sigma_mm > 0);
  CHECK(e.normal_sigma_deg > 0);
  CHECK(e.gain_spread > 0);
  CHECK(e.train_sensor != e.test_sensor);
}

TEST_CASE("errors: three objects are recognised and localised with the realistic errors on") {
  const eval::Curve c = evaluate(1.0);
  REQUIRE(c.points.size() == 12);
  const eval::CurvePoint& last = c.points.back();
  // Thresholds from bench/reliability/test_margins.py (docs/reliability.md, "Margins"): over 8 seeds the accuracy at 12
  // readings was never below 11/12 and the median translation never above 3.9 mm.
  test::margin("three objects: accuracy at 12 readings", last.accuracy, ">=", 10.0 / 12.0);
  CHECK(last.accuracy >= 10.0 / 12.0);
  REQUIRE(last.translation_mm.median);
  // Against 0.5 mm / 0.3 degree arm errors the position is found within a pose bin (8 mm wide). The angle is not
  // asserted: 60 training contacts per object are too sparse a surface for the fine pose to pin it, so each trial
  // ends either near the truth (~5 degrees) or in a look-alike rotation of the die or the mug (~90 degrees), and
  // the median of 12 such trials is a coin toss (28 to 109 degrees over seeds; paper3d's 1000 contacts give
  // 1.4 degrees, docs/evaluation.md). The fine pose's angle is tested on tiny, in the right mode
  // (tests/estimate/test_fine_pose.cpp).
  test::margin("three objects: median translation (mm) at 12 readings", *last.translation_mm.median, "<", 6.0);
  CHECK(*last.translation_mm.median < 6.0);
  // Evidence accumulates: not all right after one pair, more right at the end.
  test::margin("three objects: accuracy gained from 2 to 12 readings", last.accuracy - c.points[1].accuracy, ">", 0.0);
  CHECK(c.points[1].accuracy < last.accuracy);
}

TEST_CASE("errors: --error-scale multiplies every sigma and spread, 0 is the ideal world") {
  const ErrorModel e = three_objects().errors;
  const ErrorModel two = sim::scale_errors(e, 2.0);
  CHECK(two.position_sigma_mm == 2 * e.position_sigma_mm);
  CHECK(two.normal_sigma_deg == 2 * e.normal_sigma_deg);
  CHECK(two.gain_spread == 2 * e.gain_spread);
  CHECK(two.offset_kpa == 2 * e.offset_kpa);
  CHECK(two.noise_kpa == 2 * e.noise_kpa);
  CHECK(two.crosstalk == 2 * e.crosstalk);
  CHECK(two.full_scale_kpa == e.full_scale_kpa);  // the array's range, not an error
  CHECK(two.test_sensor == e.test_sensor);
  const ErrorModel zero = sim::scale_errors(e, 0.0);
  CHECK(zero.arm_ideal());
  CHECK(zero.gain_spread == 0);
  CHECK(zero.crosstalk == 0);
  CHECK(zero.full_scale_kpa == 0);
  CHECK_THROWS_WITH(sim::scale_errors(e, -1.0), Catch::Contains("error scale") && Catch::Contains(">= 0"));
  CHECK_THROWS_WITH(sim::scale_errors(e, 10.0), Catch::Contains("gain spread"));
  ErrorModel only_crosstalk;
  only_crosstalk.crosstalk = 0.05;
  CHECK_THROWS_WITH(sim::scale_errors(only_crosstalk, 5.0), Catch::Contains("crosstalk"));
}

TEST_CASE("errors: a simulation at an error scale records the scaled errors and moves the readings accordingly") {
  Scene s = three_objects();
  s.objects.resize(1);
  sim::SimulateOptions so;
  so.train_per_object = 30;
  so.test_per_object = 0;
  so.seed = 5;
  so.error_scale = 0.0;
  const sim::SimulatedData ideal = sim::simulate(s, so);
  CHECK(ideal.train.scene.errors.position_sigma_mm == 0);
  double worst = 0;
  for (const auto& x : ideal.train.samples) worst = std::max(worst, glm::length(x.reading.position - x.truth.position));
  CHECK(worst == 0.0);
  so.error_scale = 2.0;
  const sim::SimulatedData twice = sim::simulate(s, so);
  CHECK(twice.train.scene.errors.position_sigma_mm == 2 * s.errors.position_sigma_mm);
  worst = 0;
  for (const auto& x : twice.train.samples) worst = std::max(worst, glm::length(x.reading.position - x.truth.position));
  CHECK(worst > 0.5);
  so.error_scale = -0.5;
  CHECK_THROWS_WITH(sim::simulate(s, so), Catch::Contains("error scale"));
}

TEST_CASE("errors: the distance bins of Eq 13 widen with the training scene's position error") {
  Scene s = three_objects();  // 40 bins over 30-160 mm: 3.25 mm wide
  REQUIRE(s.appearance.dist_bins == 40);
  // 0.5 mm per axis needs bins of at least 2 sqrt(3) 0.5 = 1.73 mm: the scene's 40 stay.
  CHECK(resolve_train_parameters(s, {}).distance.count == 40);
  s.errors = sim::scale_errors(three_objects().errors, 0.0);
  CHECK(resolve_train_parameters(s, {}).distance.count == 40);
  // 2 mm needs 6.93 mm: 130 / 6.93 = 18.8, so 18 bins.
  s.errors = sim::scale_errors(three_objects().errors, 4.0);
  CHECK(resolve_train_parameters(s, {}).distance.count == 18);
  TrainOptions explicit_bins;
  explicit_bins.dist_bins = 40;
  CHECK(resolve_train_parameters(s, explicit_bins).distance.count == 40);
  s.errors.position_sigma_mm = 100.0;  // never fewer than one bin
  CHECK(resolve_train_parameters(s, {}).distance.count == 1);
}
