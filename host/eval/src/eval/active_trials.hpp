#pragma once
// Trials whose next reading is chosen after each estimate (issue 14, docs/evaluation.md "Choosing the next
// touch"). `random` is the paper's protocol (trial_runner.hpp runs it); the adaptive policies plan the next touch
// with sva::plan_next_touch over candidates sampled from the estimate's hypotheses, then
//   active:     take the true object's unused test reading nearest to the planned touch in the object's true pose;
//   active-sim: press the planned touch on the mesh (a TouchSimulator: the CLI's Embree contact controller).
// The first touch, and any step where no candidate is informative, take the trial's next random reading, as the
// random policy would; the second is planned over the first touch's contact estimate (its appearance alone).
#include <sva/dataset.hpp>
#include <sva/touch_planner.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <sva/eval/active_setup.hpp>
#include <sva/eval/results.hpp>
#include <sva/eval/trials.hpp>
#include "eval/trial_runner.hpp"

namespace sva::eval {

EvalResult run_trials_active(const Dataset& test, const TrialSetup& setup, const SessionFactory& make_session,
                             const TouchPlanner& planner, const ActiveSetup& active);

}  // namespace sva::eval
