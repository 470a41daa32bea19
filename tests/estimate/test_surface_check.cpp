// The verify stage (host/src/estimate/verify.cpp) on a family of look-alikes: one spring clamp at three
// scales (89, 120 and 171 mm; assets/scenes/lookalikes.json), simulated with the realistic errors.
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/eval/confusion.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>
#include <sva/sim/simulate.hpp>

#include "test_support.hpp"

using namespace sva;

namespace {

// The family's members only, as their own scene.
Scene family_scene(const std::string& family) {
  Scene s = load_scene("lookalikes");
  std::vector<SceneObject> members;
  for (const SceneObject& o : s.objects)
    if (o.family == family) members.push_back(o);
  s.objects = members;
  s.name = family;
  return s;
}

const sim::SimulatedData& clamps() {
  static const sim::SimulatedData d = [] {
    sim::SimulateOptions so;
    so.train_per_object = 200;
    so.test_per_object = 20;
    so.seed = 3;
    return sim::simulate(family_scene("spring_clamps"), so);
  }();
  return d;
}

Map train(const Dataset& data) {
  TrainOptions t;
  t.calibrate = false;  // the decisions are what is tested here
  return Map::train(data, t);
}

// Share of trials right after `readings` readings, over 15 trials (5 per clamp).
double accuracy_at(const Map& map, const Dataset& test, bool surface_check, std::size_t readings) {
  eval::EvalOptions o;
  o.trials = 15;
  o.max_readings = readings;
  o.progress = false;
  o.recognizer.backend = BackendKind::cpu;
  o.recognizer.surface_check = surface_check;
  const eval::Confusion c = eval::confusion_at(eval::run_evaluation(map, test, o), readings);
  std::size_t right = 0, trials = 0;
  for (std::size_t r = 0; r < c.truths.size(); ++r) right += c.right(r), trials += c.trials(r);
  return static_cast<double>(right) / static_cast<double>(trials);
}

}  // namespace

TEST_CASE("surface check on simulated clamps at three scales: the scale is told apart") {
  const sim::SimulatedData& d = clamps();
  REQUIRE(d.train.scene.objects.size() == 3);
  const Map map = train(d.train);
  // Over simulation seeds 1, 2, 3, 5 and 6 at 15 readings: 100% with the check every time; the pairs alone 73-100%.
  const double with_check = accuracy_at(map, d.test, true, 15);
  const double pairs_only = accuracy_at(map, d.test, false, 15);
  test::margin("accuracy at 15 readings, three clamp scales, surface check", with_check, ">=", 0.9);
  test::margin("the same without the surface check", pairs_only, "<=", with_check);
  CHECK(with_check >= 0.9);
  CHECK(pairs_only <= with_check);
}
