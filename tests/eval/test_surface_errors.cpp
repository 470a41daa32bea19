// MSSD and ADD-S of a whole evaluation from the built-in meshes (docs/pose-errors.md): set on every posed step,
// the same bits on 1 or 2 threads; the tiny scene's declared symmetries agree with its meshes.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/scene.hpp>

#include "eval/surface_errors.hpp"

using namespace sva;
using namespace sva::eval;

TEST_CASE("surface errors: every posed step of an evaluation gets MSSD and ADD-S, the same on 1 or 2 threads") {
  const Scene scene = load_scene("tiny");  // the die (no symmetry) and the brick (a half turn)
  REQUIRE(symmetry_warnings(scene).empty());
  const auto brick = object_symmetry(scene.objects[1]);
  REQUIRE(brick);
  CHECK(brick->rotations.size() == 2);
  EvalResult result;
  result.trials.resize(6);
  util::Rng rng(3);
  for (std::size_t t = 0; t < result.trials.size(); ++t) {
    TrialResult& trial = result.trials[t];
    trial.object = static_cast<std::uint32_t>(t % 2);
    trial.pose.R = so3::exp({rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)});
    trial.pose.T = {rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50)};
    trial.steps.resize(3);
    for (std::size_t k = 0; k < 3; ++k) {
      StepResult& s = trial.steps[k];
      s.correct = k > 0;  // the first step names another object: no pose error, no surface errors
      s.pose_valid = true;
      s.estimate = trial.pose;
      s.estimate.R = trial.pose.R * so3::exp({0.0, 0.0, k == 2 ? 3.14159265358979 : 0.05});
    }
  }
  EvalResult two = result;
  add_surface_errors(result, scene, 1);
  add_surface_errors(two, scene, 2);
  for (std::size_t t = 0; t < result.trials.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const StepResult& s = result.trials[t].steps[k];
      CHECK(s.mssd_mm.has_value() == (k > 0));
      CHECK(s.mssd_mm == two.trials[t].steps[k].mssd_mm);  // bit for bit
      CHECK(s.adds_mm == two.trials[t].steps[k].adds_mm);
      if (!s.mssd_mm) continue;
      CHECK(*s.adds_mm <= *s.mssd_mm);
      // A half turn about the object's z axis: the brick's symmetry (MSSD within the tolerance), not the die's.
      if (k == 2 && result.trials[t].object == 1) CHECK(*s.mssd_mm < brick->tolerance_mm);
      if (k == 2 && result.trials[t].object == 0) CHECK(*s.mssd_mm > 20.0);
    }
}
